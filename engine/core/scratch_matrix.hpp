#pragma once
// A dense matrix whose storage only grows: view(rows, cols) is a map onto kept storage, so
// sizes that change from call to call (one column per constraint row) allocate only when
// they exceed every earlier size. Eigen's MatX reallocates on every change of size.
// The view's contents are unspecified until written, except that storage is grown with
// zeros (std::vector::resize) and keeps what was written (zeroed_columns.hpp relies on both).
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

class ScratchMatrix {
 public:
  Eigen::Map<MatX> view(Eigen::Index rows, Eigen::Index cols) {
    const std::size_t needed = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
    if (m_storage.size() < needed) m_storage.resize(needed);
    return Eigen::Map<MatX>(m_storage.data(), rows, cols);
  }
  Eigen::Map<VecX> vector(Eigen::Index size) { return Eigen::Map<VecX>(view(size, 1).data(), size); }
  // The storage as it is (no growth).
  double* data() { return m_storage.data(); }

 private:
  std::vector<double> m_storage;
};

}  // namespace sinew
