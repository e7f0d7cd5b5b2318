#include "engine/constraints/solve_column_cache.hpp"

#include <algorithm>

namespace sinew {

int SolveColumnCache::find(const RowTable& rows, int i) const {
  const uint64_t key = rows.key[i];
  const auto it = std::lower_bound(m_keys.begin(), m_keys.end(), std::make_pair(key, -1));
  if (it == m_keys.end() || it->first != key) return -1;
  const int c = it->second;
  const int n = rows.begin[i + 1] - rows.begin[i];
  if (m_rows.begin[c + 1] - m_rows.begin[c] != n) return -1;
  // Exact comparison: a column is reused only for the very same J_i.
  for (int k = 0; k < n; ++k) {
    const int a = rows.begin[i] + k, b = m_rows.begin[c] + k;
    if (rows.nodes[a] != m_rows.nodes[b] || rows.jac[a] != m_rows.jac[b]) return -1;
  }
  return c;
}

}  // namespace sinew
