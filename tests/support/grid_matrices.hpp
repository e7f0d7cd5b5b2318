#pragma once
// Test matrices of the solver tests: `copies` disconnected copies of 7 I minus a 3D grid's
// adjacency (nx^3 unknowns each, -1 to each grid neighbour: the grid Laplacian plus
// (7 - degree) I), no entry between copies. SPD with condition number below 1 + 12 = 13, so solutions are good to a few ulps
// times that. Several copies stand for several bodies: L is block-diagonal.
#include <vector>

#include "engine/assembly/system_pattern.hpp"  // SparseMatrix
#include "engine/core/types.hpp"

namespace sinew::test {

inline SparseMatrix grid_laplacian(int nx, int copies = 1) {
  const int n = nx * nx * nx;
  const auto index = [nx](int i, int j, int k) { return (k * nx + j) * nx + i; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int copy = 0; copy < copies; ++copy)
    for (int k = 0; k < nx; ++k)
      for (int j = 0; j < nx; ++j)
        for (int i = 0; i < nx; ++i) {
          const int a = copy * n + index(i, j, k);
          entries.emplace_back(a, a, 7.0);
          const auto link = [&](int b) {
            entries.emplace_back(a, copy * n + b, -1.0);
            entries.emplace_back(copy * n + b, a, -1.0);
          };
          if (i + 1 < nx) link(index(i + 1, j, k));
          if (j + 1 < nx) link(index(i, j + 1, k));
          if (k + 1 < nx) link(index(i, j, k + 1));
        }
  SparseMatrix A(copies * n, copies * n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

// The same operator on 3 unknowns a grid point, stored as a step matrix is (the system
// pattern's node blocks, system_pattern.hpp: every 3 x 3 block whole, its off-diagonal
// entries explicit zeros): grid_laplacian(nx) times I_3, with the same eigenvalues.
inline SparseMatrix node_blocked_grid_laplacian(int nx) {
  const SparseMatrix scalar = grid_laplacian(nx);
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < scalar.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(scalar, j); it; ++it)
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) entries.emplace_back(3 * it.row() + r, 3 * j + c, r == c ? it.value() : 0.0);
  SparseMatrix A(3 * scalar.rows(), 3 * scalar.cols());
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

}  // namespace sinew::test
