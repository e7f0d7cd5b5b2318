#pragma once
// The block G = E^T H^-1 E of the inverse of the step's system matrix H on the nodes that
// constraint rows touch (E selects their 3 DOFs each). Every Delassus product the
// constraint solve needs is J H^-1 J^T = Jc G Jc^T with Jc the rows' Jacobians on those
// nodes, so H^-1 is needed on 3 columns per touched node, not one column per row: the
// rows of strain limits (up to 18 per tet, 42 with the pair cuts), of contacts embedded in the same element and
// their friction rows all share node columns. Columns are kept for the life of one
// factorisation of H, whatever the rows' Jacobians do across SQP iterations; a node
// touched for the first time costs 3 solves.
#include <vector>

#include "engine/core/scratch_matrix.hpp"
#include "engine/core/zeroed_columns.hpp"
#include "engine/core/types.hpp"

namespace sinew {

class TouchedInverse {
 public:
  // Forget everything: H was refactorised. `free_nodes` is the number of free nodes.
  void reset(int free_nodes);
  // H was refactorised but G is kept (solver.delassus_reuse): from now on its columns are
  // those of an earlier H, an approximation, until reset(). Columns added later come from
  // the current H.
  void keep_stale() { m_stale = true; }
  bool stale() const { return m_stale; }

  // Adds the free nodes of `nodes` (free indices, any order, repeats allowed) that have no
  // columns yet; `solve_many(B, X, rows)` must compute X = H^-1 B (X given with B's size, a
  // map onto kept storage) at least on `rows` (the touched nodes' DOFs, the only rows G
  // reads: LinearSolver::solve_many's wanted rows), called as `solve_many(B, X, rows,
  // pattern)` with B's ZeroedColumns::Pattern (each column's one non-zero). Returns the
  // columns solved.
  template <typename SolveMany>
  int require(const std::vector<int>& nodes, SolveMany&& solve_many);

  // Changes with every change of G's entries (reset, added columns): equal versions, the same G.
  long version() const { return m_version; }

  // Position of free node f in G (its DOFs are 3 local .. 3 local + 2), or -1.
  int local(int f) const { return m_local[f]; }
  int size() const { return static_cast<int>(m_nodes.size()); }  // touched nodes
  // G on the touched nodes: 3 size() x 3 size(), symmetric.
  auto block() const { return m_G.topLeftCorner(3 * size(), 3 * size()); }

 private:
  void grow(int nodes);  // capacity for at least `nodes` touched nodes, keeping G
  void add_columns(const std::vector<int>& added, const Eigen::Ref<const MatX>& X);

  bool m_stale = false;
  long m_version = 0;
  std::vector<int> m_local;  // per free node: local index or -1
  std::vector<int> m_nodes;  // local index -> free node
  MatX m_G;                  // capacity x capacity (3 DOFs per node); the leading block is valid
  std::vector<int> m_added;
  std::vector<int> m_rows;   // require's: the DOFs of every touched node, old and added
  ZeroedColumns m_B;
  ScratchMatrix m_X;
};

template <typename SolveMany>
int TouchedInverse::require(const std::vector<int>& nodes, SolveMany&& solve_many) {
  m_added.clear();
  for (const int f : nodes)
    if (f >= 0 && m_local[f] < 0) {
      m_local[f] = size() + static_cast<int>(m_added.size());
      m_added.push_back(f);
    }
  if (m_added.empty()) return 0;
  const int n = 3 * static_cast<int>(m_local.size());
  const int columns = 3 * static_cast<int>(m_added.size());
  Eigen::Map<MatX> B = m_B.view(n, columns), X = m_X.view(n, columns);
  const ZeroedColumns::ClearOnExit clear_B{m_B};
  for (int k = 0; k < columns; ++k) m_B.set(B, 3 * m_added[k / 3] + k % 3, k, 1.0);
  m_rows.clear();
  for (const std::vector<int>* list : {&m_nodes, &m_added})
    for (const int f : *list)
      for (int d = 0; d < 3; ++d) m_rows.push_back(3 * f + d);
  solve_many(B, X, m_rows, &m_B.pattern(columns));
  add_columns(m_added, X);
  return columns;
}

}  // namespace sinew
