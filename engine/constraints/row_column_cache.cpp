#include "engine/constraints/row_column_cache.hpp"

namespace sinew {

bool RowColumnCache::matches(const Entry& entry, const RowTable& rows, int i) const {
  const int begin = rows.begin[i], count = rows.begin[i + 1] - begin;
  if (static_cast<int>(entry.nodes.size()) != count) return false;
  for (int k = 0; k < count; ++k)
    if (entry.nodes[k] != rows.nodes[begin + k] || entry.jac[k] != rows.jac[begin + k]) return false;
  return true;
}

void RowColumnCache::store(const RowTable& rows, int i, const double* y, int free_dofs) {
  Entry& entry = m_entries[rows.key[i]];
  entry.nodes.assign(rows.nodes.begin() + rows.begin[i], rows.nodes.begin() + rows.begin[i + 1]);
  entry.jac.assign(rows.jac.begin() + rows.begin[i], rows.jac.begin() + rows.begin[i + 1]);
  entry.y = Eigen::Map<const VecX>(y, free_dofs);
}

}  // namespace sinew
