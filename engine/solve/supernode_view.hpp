#pragma once
// One supernode of CHOLMOD's supernodal LL^T factor (real, int indices), as the block and
// tree solves (supernodal_block_solve.hpp, supernodal_tree_solve.hpp) read it.
#include <cholmod.h>

namespace sinew {

struct SupernodeView {
  int first, columns, height;  // its first row of L, its columns, its rows
  const double* L;             // height x columns, column-major
  const int* rows;             // its rows of L, the triangle's first
};

inline SupernodeView supernode_view(const cholmod_factor& L, int s) {
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  return SupernodeView{super[s], super[s + 1] - super[s], pi[s + 1] - pi[s],
                       static_cast<const double*>(L.x) + px[s], static_cast<const int*>(L.s) + pi[s]};
}

}  // namespace sinew
