#pragma once
// Right-hand sides with a few non-zeros per column (a row's stencil, a node's unit
// vectors) over a whole system: their storage is kept all zero between uses, and a use
// sets its entries, solves, then zeroes just those again, instead of zeroing n x m values
// first (the default demo's 600 columns of 5,850 DOFs: 28 MB a call).
#include <cassert>
#include <utility>
#include <vector>

#include "engine/core/scratch_matrix.hpp"

namespace sinew {

class ZeroedColumns {
 public:
  // The n x m block, all zero (storage grown with zeros when needed).
  Eigen::Map<MatX> view(Eigen::Index n, Eigen::Index m) {
    m_rows = n;
    return m_storage.view(n, m);
  }
  // B(i, j) = value, remembered for clear().
  void set(Eigen::Map<MatX>& B, Eigen::Index i, Eigen::Index j, double value) {
    B(i, j) = value;
    m_set.emplace_back(i, j);
  }
  void add(Eigen::Map<MatX>& B, Eigen::Index i, Eigen::Index j, double value) {
    B(i, j) += value;
    m_set.emplace_back(i, j);
  }
  // Where columns 0 .. m - 1 may be non-zero (set/add since the last clear(), which wrote
  // the columns in order): column j's rows are rows[start[j] .. start[j + 1]).
  struct Pattern {
    std::vector<int> start, rows;
  };
  const Pattern& pattern(Eigen::Index m) {
    m_pattern.start.assign(m + 1, 0);
    m_pattern.rows.clear();
    for (const auto& [i, j] : m_set) {
      assert(j < m && (m_pattern.rows.empty() || j >= m_last_column));
      m_last_column = j;
      m_pattern.rows.push_back(static_cast<int>(i));
      ++m_pattern.start[j + 1];
    }
    for (Eigen::Index j = 0; j < m; ++j) m_pattern.start[j + 1] += m_pattern.start[j];
    return m_pattern;
  }
  // Zeroes what set/add wrote since the last clear().
  void clear() {
    double* data = m_storage.view(m_rows, 1).data();
    for (const auto& [i, j] : m_set) data[j * m_rows + i] = 0.0;
    m_set.clear();
  }
  // Clears on scope exit, whatever way the scope is left (a solve that throws included).
  struct ClearOnExit {
    ZeroedColumns& columns;
    ~ClearOnExit() { columns.clear(); }
  };

 private:
  ScratchMatrix m_storage;  // resize() value-initialises: new storage is zero
  Eigen::Index m_rows = 0;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> m_set;
  Pattern m_pattern;
  Eigen::Index m_last_column = 0;
};

}  // namespace sinew
