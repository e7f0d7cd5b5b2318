#include "engine/constraints/row_column_cache.hpp"

#include <iterator>

namespace sinew {

bool RowColumnCache::matches(const Entry& entry, const RowTable& rows, int i, int free_dofs) const {
  const int begin = rows.begin[i], count = rows.begin[i + 1] - begin;
  if (static_cast<int>(entry.nodes.size()) != count || entry.y.size() != free_dofs) return false;
  for (int k = 0; k < count; ++k)
    if (entry.nodes[k] != rows.nodes[begin + k] || entry.jac[k] != rows.jac[begin + k]) return false;
  return true;
}

void RowColumnCache::store(const RowTable& rows, int i, const double* y, int free_dofs) {
  Entry& entry = m_entries[rows.key[i]];
  entry.nodes.assign(rows.nodes.begin() + rows.begin[i], rows.nodes.begin() + rows.begin[i + 1]);
  entry.jac.assign(rows.jac.begin() + rows.begin[i], rows.jac.begin() + rows.begin[i + 1]);
  entry.y = Eigen::Map<const VecX>(y, free_dofs);
  entry.last_call = m_call;
}

void RowColumnCache::evict(int rows) {
  if (static_cast<int>(m_entries.size()) <= rows) return;
  for (auto it = m_entries.begin(); it != m_entries.end();)
    it = it->second.last_call == m_call ? std::next(it) : m_entries.erase(it);
}

}  // namespace sinew
