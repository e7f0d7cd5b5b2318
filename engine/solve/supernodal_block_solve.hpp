#pragma once
// A = P^T L L^T P solved for a block of right-hand sides on CHOLMOD's supernodal factor, by
// loops over its supernodes' dense blocks instead of CHOLMOD's BLAS calls. Debian's serial
// OpenBLAS may not be called from two threads at once, and its pthread build serialises
// concurrent calls on a lock (measured: two threads no faster than one), so blocks of
// columns run in parallel only through code that calls no BLAS. The forward pass skips
// supernodes where the whole block is still zero: H^-1 on a few nodes (touched_inverse.hpp)
// has unit-vector columns, whose forward solve reaches only their elimination-tree paths.
// The backward pass skips supernodes whose solution is zero: not reached by the forward pass,
// and zero on all the rows below their triangle. With several bodies L is block-diagonal
// (its elimination tree a forest), so a block on one body's nodes works on that body's part
// of L alone. A caller that needs the solution on some rows only (the block of H^-1 on the
// nodes constraint rows touch, touched_inverse.hpp) passes them as a mask of "wanted"
// supernodes: those holding the rows and their ancestors, which are all the backward pass
// reads to find them; the others are skipped, and the solution there is left at zero.
#include <cholmod.h>

#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

class SupernodalBlockSolve {
 public:
  static constexpr int kMaxWidth = 16;  // columns per block at most

  // Per-thread buffers, sized by prepare(): a warm solve allocates nothing.
  struct Workspace {
    std::vector<double> y;      // n rows of kMaxWidth values: the block in the factor's order
    std::vector<char> nonzero;  // per supernode: the forward pass reached it; after the backward
                                // pass, its solution may be nonzero
    int backward_supernodes = 0;  // supernodes the last solve's backward pass worked on (tests)
  };

  // Reads L's supernode structure (once per symbolic analysis; L supernodal LL^T, int indices).
  void analyse(const cholmod_factor& L);
  bool analysed_for(const cholmod_factor& L) const { return m_factor == &L && m_n == static_cast<int>(L.n); }
  void prepare(Workspace& ws) const;
  // Marks in `wanted` (one flag per supernode, resized) the supernodes holding `rows` (rows
  // of A) and their ancestors in the elimination tree: the mask for solve's `wanted`.
  void mark_wanted(const std::vector<int>& rows, std::vector<char>& wanted) const;
  // Where a column's nonzeros may be: `count` rows of A (duplicates allowed) that hold all of
  // them, so that a sparse right-hand side is read there instead of over all n rows.
  struct ColumnRows {
    const int* rows = nullptr;
    int count = 0;
  };
  // The first position, in the factor's order, of a nonzero of `column` (n values); n if none.
  // With `candidates`, only those rows are read.
  int first_position(const double* column, const ColumnRows* candidates = nullptr) const;
  // x_c = A^-1 b_c for `width` <= kMaxWidth columns: b[c] and x[c] point to n values each
  // (the columns may lie anywhere: the caller's own storage, no copy into a block). With
  // `wanted` (mark_wanted's mask), x is exact on the wanted supernodes' rows, bit for bit as
  // without it, and zero on the others.
  void solve(const cholmod_factor& L, const double* const* b, double* const* x, int width, Workspace& ws,
             const char* wanted = nullptr, const ColumnRows* candidates = nullptr) const;
  // The same for column-major B and X (leading dimensions ldb and ldx).
  void solve(const cholmod_factor& L, const double* B, int ldb, double* X, int ldx, int width,
             Workspace& ws, const char* wanted = nullptr) const;

 private:
  const cholmod_factor* m_factor = nullptr;
  int m_n = 0;
  std::vector<int> m_supernode_of;  // per row of L: its supernode
  std::vector<int> m_position;      // per row of A: its row in L (the inverse permutation)
  std::vector<int> m_parent;        // per supernode: its parent in the elimination tree, or -1
};

}  // namespace sinew
