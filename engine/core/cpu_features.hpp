#pragma once
// Whether the hand-vectorised kernels (add_scaled.hpp, supernode_kernels_avx2.hpp,
// tree_kernels.hpp, invariant_tet_blocks.hpp, compute_rotation_variant_svds in
// rotation_variant_svd.hpp) take their
// AVX2 paths: the CPU has AVX2 (checked once, at start-up; the build targets baseline x86-64)
// and no caller turned them off. Both paths give the same bits (no fused multiply-add), so
// this only changes speed; tests turn it off to compare.
#include <atomic>

namespace sinew {

namespace detail {
extern std::atomic<bool> g_use_avx2;  // the CPU's flag, and allow_avx2's
}  // namespace detail

// A relaxed load: one plain read per call (PGS calls it per row update).
inline bool use_avx2() { return detail::g_use_avx2.load(std::memory_order_relaxed); }
// allowed false: the baseline paths; true: AVX2 where the CPU has it (the default).
void allow_avx2(bool allowed);

// Turns the AVX2 paths off for its lifetime, and back to what they were after (tests).
class BaselineKernelsOnly {
 public:
  BaselineKernelsOnly() : m_was(use_avx2()) { allow_avx2(false); }
  ~BaselineKernelsOnly() { allow_avx2(m_was); }
  BaselineKernelsOnly(const BaselineKernelsOnly&) = delete;
  BaselineKernelsOnly& operator=(const BaselineKernelsOnly&) = delete;

 private:
  bool m_was;
};

}  // namespace sinew
