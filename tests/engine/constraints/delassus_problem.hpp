#pragma once
// Random LCP problems for the Delassus operator's tests: an SPD H on the free DOFs, rows of a
// few nodes with random Jacobian blocks, and H^-1 on the touched nodes.
#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Cholesky>

#include "engine/constraints/row_table.hpp"
#include "engine/constraints/touched_inverse.hpp"

namespace sinew::test {

struct Problem {
  int nodes = 0;              // global nodes; node 0 is fixed
  std::vector<int> free_index;
  MatX H;                     // SPD on the free DOFs
  RowTable rows;
};

// Rows of 1 to 4 distinct nodes with random Jacobian blocks, some on the fixed node.
inline Problem random_problem(int nodes, int rows, std::mt19937& rng) {
  Problem p;
  p.nodes = nodes;
  p.free_index.resize(nodes);
  for (int n = 0; n < nodes; ++n) p.free_index[n] = n - 1;  // node 0 fixed
  const int dofs = 3 * (nodes - 1);
  std::normal_distribution<double> normal;
  MatX B(dofs, dofs);
  for (int i = 0; i < dofs; ++i)
    for (int j = 0; j < dofs; ++j) B(i, j) = normal(rng);
  p.H = B * B.transpose() + dofs * MatX::Identity(dofs, dofs);
  std::uniform_int_distribution<int> node(0, nodes - 1), size(1, 4);
  for (int i = 0; i < rows; ++i) {
    p.rows.add_row(RowKind::Strain, 0, 0, 1e300, i);
    std::vector<int> used;
    for (int k = size(rng); k > 0; --k) {
      const int n = node(rng);
      if (std::find(used.begin(), used.end(), n) != used.end()) continue;
      used.push_back(n);
      p.rows.add_entry(n, Vec3(normal(rng), normal(rng), normal(rng)));
    }
  }
  return p;
}

inline MatX jacobian(const Problem& p) {
  MatX J = MatX::Zero(p.rows.size(), p.H.rows());
  for (int i = 0; i < p.rows.size(); ++i)
    for (int e = p.rows.begin[i]; e < p.rows.begin[i + 1]; ++e)
      if (const int f = p.free_index[p.rows.nodes[e]]; f >= 0) J.block<1, 3>(i, 3 * f) += p.rows.jac[e].transpose();
  return J;
}

// The touched inverse for p's rows, filled in two batches (to exercise growth).
inline TouchedInverse touched_inverse(const Problem& p, const Eigen::LLT<MatX>& llt, std::vector<int>& local_node) {
  TouchedInverse inverse;
  inverse.reset(p.nodes - 1);
  std::vector<int> free_nodes;
  for (const int n : p.rows.nodes) free_nodes.push_back(p.free_index[n]);
  // X right on the wanted rows only, as LinearSolver::solve_many promises: any other row G
  // read would spoil the comparisons with J H^-1 J^T below.
  const auto solve = [&](const auto& B, auto& X, const std::vector<int>& rows, const ZeroedColumns::Pattern*) {
    const MatX full = llt.solve(B);
    X.setConstant(std::numeric_limits<double>::quiet_NaN());
    for (const int r : rows) X.row(r) = full.row(r);
  };
  const std::vector<int> first(free_nodes.begin(), free_nodes.begin() + free_nodes.size() / 2);
  CHECK(inverse.require(first, solve) > 0);
  inverse.require(free_nodes, solve);
  CHECK(inverse.require(free_nodes, solve) == 0);  // nothing new the second time
  local_node.assign(p.nodes, -1);
  for (int n = 0; n < p.nodes; ++n)
    if (p.free_index[n] >= 0) local_node[n] = inverse.local(p.free_index[n]);
  return inverse;
}


}  // namespace sinew::test
