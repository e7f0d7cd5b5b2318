#include "engine/constraints/row_column_cache.hpp"

#include <algorithm>

namespace sinew {

namespace {
constexpr int kWidestStencil = 16;
}  // namespace

bool RowColumnCache::matches(const Entry& entry, const RowTable& rows, int i, int free_dofs) const {
  const int begin = rows.begin[i], count = rows.begin[i + 1] - begin;
  if (static_cast<int>(entry.nodes.size()) != count || entry.y.size() != free_dofs) return false;
  for (int k = 0; k < count; ++k)
    if (entry.nodes[k] != rows.nodes[begin + k] || entry.jac[k] != rows.jac[begin + k]) return false;
  return true;
}

RowColumnCache::Entry* RowColumnCache::find(uint64_t key) {
  const auto it = std::lower_bound(m_index.begin(), m_index.end(), std::make_pair(key, -1));
  return it != m_index.end() && it->first == key ? &m_slots[it->second] : nullptr;
}

void RowColumnCache::reset() {
  for (const auto& [key, slot] : m_index) m_free_slots.push_back(slot);
  m_index.clear();
}

void RowColumnCache::ensure_slots(int entries) {
  if (static_cast<int>(m_slots.size()) >= entries) return;
  m_index.reserve(entries);
  m_free_slots.reserve(entries);
  m_missing.reserve(entries);
  m_kept.reserve(entries);
  while (static_cast<int>(m_slots.size()) < entries) {
    m_free_slots.push_back(static_cast<int>(m_slots.size()));
    m_slots.emplace_back();
    // Room for the widest stencil (a body contact spans two hex cells), so that recycling
    // the slot for any row allocates nothing. Its column is sized when the slot is first
    // used: 2 m full columns up front would double the cache's memory on large lattices.
    m_slots.back().nodes.reserve(kWidestStencil);
    m_slots.back().jac.reserve(kWidestStencil);
  }
}

void RowColumnCache::store(const RowTable& rows, int i, const double* y, int free_dofs) {
  const uint64_t key = rows.key[i];
  Entry* entry = find(key);
  if (!entry) {
    ensure_slots(static_cast<int>(m_index.size()) + 1);
    const int slot = m_free_slots.back();
    m_free_slots.pop_back();
    m_index.insert(std::lower_bound(m_index.begin(), m_index.end(), std::make_pair(key, -1)), {key, slot});
    entry = &m_slots[slot];
  }
  entry->nodes.assign(rows.nodes.begin() + rows.begin[i], rows.nodes.begin() + rows.begin[i + 1]);
  entry->jac.assign(rows.jac.begin() + rows.begin[i], rows.jac.begin() + rows.begin[i + 1]);
  entry->y.resize(free_dofs);
  entry->y = Eigen::Map<const VecX>(y, free_dofs);
  entry->last_call = m_call;
}

void RowColumnCache::evict(int rows) {
  if (static_cast<int>(m_index.size()) <= rows) return;
  const auto unused = std::remove_if(m_index.begin(), m_index.end(), [&](const std::pair<uint64_t, int>& e) {
    if (m_slots[e.second].last_call == m_call) return false;
    m_free_slots.push_back(e.second);
    return true;
  });
  m_index.erase(unused, m_index.end());
}

}  // namespace sinew
