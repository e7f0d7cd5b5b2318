// Included (no include guard: once per use) after a file's last #include, to compile the
// functions that follow for AVX2, up to engine/core/avx2_region_end.hpp. GCC's target
// attribute does not reach template instantiations, hence a pragma; clang has its own
// (clang++ 14 compiles such files, checked by hand, as no CI build compiles the engine with
// clang). A file using it is compiled outside the unity batches (engine/CMakeLists.txt), so
// that no inline function of a header is compiled for AVX2 by it.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
