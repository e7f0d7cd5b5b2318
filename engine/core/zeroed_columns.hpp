#pragma once
// Right-hand sides with a few non-zeros per column (a row's stencil, a node's unit
// vectors) over a whole system: their storage is kept all zero between uses, and a use
// sets its entries, solves, then zeroes just those again, instead of zeroing n x m values
// first (the default demo's 600 columns of 5,850 DOFs: 28 MB a call).
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
};

}  // namespace sinew
