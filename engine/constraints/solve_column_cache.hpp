#pragma once
// Columns H^-1 J_i^T of the constraint solve, kept for rows whose Jacobian has not changed
// since they were computed with the same factorisation of H. Contact rows keep their
// Jacobian across SQP iterations (a plane's normal and tangents, a vertex's fixed
// weights), so later iterations solve only for the rows that are new or moved; energy and
// strain rows, whose Jacobians follow x, miss and are solved again.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/core/types.hpp"

namespace sinew {

class SolveColumnCache {
 public:
  // Forget every column: the factorisation of H changed.
  void invalidate() { m_keys.clear(); }

  // Y = H^-1 Jt column by column: copies the columns cached for rows of `rows` with the
  // same key, stencil and Jacobian; `solve_many(B, X)` computes the others (X = H^-1 B).
  // Then caches every column of Y. Returns the number of columns solved.
  template <typename SolveMany>
  int columns(const RowTable& rows, const MatX& Jt, MatX& Y, SolveMany&& solve_many);

 private:
  // Index of the cached row equal to row i of `rows`, or -1.
  int find(const RowTable& rows, int i) const;

  std::vector<std::pair<uint64_t, int>> m_keys;  // sorted key -> row of m_rows / column of m_Y
  RowTable m_rows;
  MatX m_Y;
  std::vector<int> m_missing;
  MatX m_B, m_X;
};

template <typename SolveMany>
int SolveColumnCache::columns(const RowTable& rows, const MatX& Jt, MatX& Y, SolveMany&& solve_many) {
  const int m = rows.size();
  Y.resize(Jt.rows(), m);
  m_missing.clear();
  for (int i = 0; i < m; ++i) {
    const int c = find(rows, i);
    if (c >= 0) Y.col(i) = m_Y.col(c);
    else m_missing.push_back(i);
  }
  if (!m_missing.empty()) {
    m_B.resize(Jt.rows(), Eigen::Index(m_missing.size()));
    for (std::size_t k = 0; k < m_missing.size(); ++k) m_B.col(Eigen::Index(k)) = Jt.col(m_missing[k]);
    solve_many(m_B, m_X);
    for (std::size_t k = 0; k < m_missing.size(); ++k) Y.col(m_missing[k]) = m_X.col(Eigen::Index(k));
  }
  m_rows = rows;
  m_Y = Y;
  m_keys.resize(std::size_t(m));
  for (int i = 0; i < m; ++i) m_keys[std::size_t(i)] = {rows.key[i], i};
  std::sort(m_keys.begin(), m_keys.end());
  return int(m_missing.size());
}

}  // namespace sinew
