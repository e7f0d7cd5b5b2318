// Ends the AVX2 region begun by engine/core/avx2_region_begin.hpp.
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
