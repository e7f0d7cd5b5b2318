#pragma once
// Right-hand sides with a few non-zeros per column (a row's stencil, a node's unit
// vectors) over a whole system: their storage is kept all zero between uses, and a use
// sets its entries, solves, then zeroes just those again, instead of zeroing n x m values
// first (the default demo's 600 columns of 5,850 DOFs: 28 MB a call). The solve must not
// write into it (X is another matrix): clear() zeroes only what set/add wrote.
#include <stdexcept>
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
  // Recorded before written: a record that fails to grow leaves nothing unrecorded.
  void set(Eigen::Map<MatX>& B, Eigen::Index i, Eigen::Index j, double value) {
    m_set.emplace_back(i, j);
    B(i, j) = value;
  }
  void add(Eigen::Map<MatX>& B, Eigen::Index i, Eigen::Index j, double value) {
    m_set.emplace_back(i, j);
    B(i, j) += value;
  }
  // Where columns 0 .. m - 1 may be non-zero (set/add since the last clear(), in any order):
  // column j's rows are rows[start[j] .. start[j + 1]), a counting sort of the records.
  struct Pattern {
    std::vector<int> start, rows;
  };
  const Pattern& pattern(Eigen::Index m) {
    m_pattern.start.assign(m + 1, 0);
    for (const auto& [i, j] : m_set) {
      if (j < 0 || j >= m) throw std::logic_error("ZeroedColumns::pattern: an entry beyond the columns asked for");
      ++m_pattern.start[j + 1];
    }
    for (Eigen::Index j = 0; j < m; ++j) m_pattern.start[j + 1] += m_pattern.start[j];
    m_pattern.rows.resize(m_set.size());
    m_next.assign(m_pattern.start.begin(), m_pattern.start.end() - 1);
    for (const auto& [i, j] : m_set) m_pattern.rows[m_next[j]++] = static_cast<int>(i);
    return m_pattern;
  }
  // Zeroes what set/add wrote since the last clear().
  void clear() {
    double* data = m_storage.data();  // no growth: the entries were written through a view of it
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
  std::vector<int> m_next;
};

}  // namespace sinew
