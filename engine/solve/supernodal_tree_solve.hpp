#pragma once
// One right-hand side solved on CHOLMOD's supernodal factor (A = P^T L L^T P) by two
// threads: the elimination tree's subtrees are independent in both passes, so the
// supernodes split into two sets of whole subtrees ("bins", of about equal work) and the
// rest, their ancestors ("top"). Forward: each bin runs on its own copy of the vector (its
// updates to top rows accumulate there), the copies are summed into the top rows in a fixed
// order, then the top runs. Backward: the top first, then the bins, which only read top rows.
// The top's wide supernodes (the root) run on both threads too (wide_supernode_passes.hpp).
// The split depends on the factor alone: the result is bit-identical for any thread count.
// Per supernode, BLAS-2 work by sinew's own passes (tree_kernels.hpp: no BLAS call, as Debian's
// serial OpenBLAS may not run on two threads at once), on the factor's values or a
// single-precision copy of them. CHOLMOD's single solve runs on one thread, and a tree
// with no split is solved here in order on one thread (sinew_bench_single_solve: faster than
// CHOLMOD's); SQP, Newton-PCG and the step's velocity solve take several single solves a step.
#include <cholmod.h>

#include <array>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/solve/wide_supernode_passes.hpp"

namespace sinew {

class SupernodalTreeSolve {
 public:
  // Reads L's supernodal elimination tree and chooses the split (once per symbolic
  // analysis). Leaves it unusable (usable() false) when the tree has no useful split: then
  // the caller solves on one thread.
  void analyse(const cholmod_factor& L);
  bool analysed_for(const cholmod_factor& L) const { return m_factor == &L && m_n == static_cast<int>(L.n); }
  bool usable() const { return m_usable; }
  // Work in the bins and the top, as factor entries (tests, docs).
  long bin_entries(int b) const { return m_bin_entries[b]; }
  long top_entries() const { return m_top_entries; }
  // Columns of the top's widest supernode (tests: whether WideSupernodePasses takes part).
  int widest_top_columns() const { return m_widest_top; }
  // Whether the supernodes can be solved in their own order on one thread (every parent
  // after its children; CHOLMOD's postorder): the single-precision solve below needs it.
  bool ordered() const { return m_ordered; }
  // x = A^-1 b (n values each; may not alias): with the split when usable(), else in order
  // on one thread (ordered() needed). Allocates nothing once its buffers are sized.
  void solve(const cholmod_factor& L, const double* b, double* x);
  // The same with L~, the factor with `values` (a single-precision copy of L.x, L.xsize
  // entries), in double arithmetic (tree_kernels.hpp): x = P^T (L~ L~^T)^-1 P b. A
  // preconditioner's solve: half the memory read, within a few single-precision round-offs
  // of A^-1 b.
  void solve(const cholmod_factor& L, const float* values, const double* b, double* x);

 private:
  struct Range {
    int first, last;  // supernodes first..last: one subtree, in the factor's (post)order
  };
  template <class Real>
  void solve_with(const cholmod_factor& L, const Real* values, const double* b, double* x);

  const cholmod_factor* m_factor = nullptr;
  int m_n = 0;
  bool m_usable = false, m_ordered = false;
  std::array<std::vector<Range>, 2> m_bins;
  std::vector<int> m_top;       // supernodes outside the bins, ascending
  std::vector<int> m_top_rows;  // their rows of L
  std::array<long, 2> m_bin_entries{};
  long m_top_entries = 0;
  int m_widest_top = 0;
  int m_max_below = 0;          // rows below a supernode's triangle, at most
  std::vector<double> m_y;      // the shared vector, in the factor's order
  std::array<std::vector<double>, 2> m_bin_y, m_gather;  // per bin: its copy, its gather buffer
  WideSupernodePasses m_wide;   // the top's wide supernodes on two threads
};

}  // namespace sinew
