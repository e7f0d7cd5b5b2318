#pragma once
// One supernode of CHOLMOD's supernodal LL^T factor (real, int indices), as the block and
// tree solves (supernodal_block_solve.hpp, supernodal_tree_solve.hpp) read it: from the
// factor's own values, or from a single-precision copy of them in the same layout (the tree
// solve's preconditioner passes, supernodal_tree_solve.hpp).
#include <cholmod.h>

namespace sinew {

template <class Real>
struct BasicSupernodeView {
  int first, columns, height;  // its first row of L, its columns, its rows
  const Real* L;               // height x columns, column-major
  const int* rows;             // its rows of L, the triangle's first
};
using SupernodeView = BasicSupernodeView<double>;
using SingleSupernodeView = BasicSupernodeView<float>;

// Supernode s with its values from `values`: L.x itself, or a copy of it (L.xsize entries).
template <class Real>
BasicSupernodeView<Real> supernode_view(const cholmod_factor& L, int s, const Real* values) {
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  return BasicSupernodeView<Real>{super[s], super[s + 1] - super[s], pi[s + 1] - pi[s], values + px[s],
                                  static_cast<const int*>(L.s) + pi[s]};
}

inline SupernodeView supernode_view(const cholmod_factor& L, int s) {
  return supernode_view(L, s, static_cast<const double*>(L.x));
}

}  // namespace sinew
