#include "engine/constraints/row_column_cache.hpp"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
  for (const int f : m_nodes) m_node_slot[f] = -1;
  m_nodes.clear();
  m_nodes_chosen = false;
  m_previous_keys.clear();
  m_have_previous_call.value = false;
  m_previous_from_entries = false;
  m_same_as_previous = false;
  m_generation = 0;
  for (const int dof : m_wanted) m_is_wanted[dof] = 0;
  m_wanted.clear();
  m_node_generation = kComplete;
  m_generations.clear();
  m_complete = true;
}

void RowColumnCache::want_stencils(const RowTable& rows, const std::vector<int>& free_index, int free_dofs) {
  if (static_cast<int>(m_is_wanted.size()) < free_dofs) {  // once per system size: no allocation after
    m_is_wanted.resize(free_dofs, 0);
    m_wanted.reserve(free_dofs);
  }
  for (int e = 0; e < rows.begin[rows.size()]; ++e)
    if (const int f = free_index[rows.nodes[e]]; f >= 0 && !m_is_wanted[3 * f])
      for (int c = 0; c < 3; ++c) {
        m_is_wanted[3 * f + c] = 1;
        m_wanted.push_back(3 * f + c);
      }
}

void RowColumnCache::remember_call(const RowTable& rows) {
  const int m = rows.size();
  // Kept this call means the entry's column is unchanged since the call before stored or
  // kept it; that call's W used it only if it, too, took every column from an entry.
  const bool all_kept = static_cast<int>(m_kept.size()) == m;
  m_same_as_previous = all_kept && m_previous_from_entries && m_previous_keys.size() == static_cast<size_t>(m) &&
                       std::equal(m_previous_keys.begin(), m_previous_keys.end(), rows.key.begin());
  m_previous_keys.assign(rows.key.begin(), rows.key.begin() + m);
  m_previous_begin.assign(rows.begin.begin(), rows.begin.begin() + m + 1);
  m_previous_nodes.assign(rows.nodes.begin(), rows.nodes.begin() + rows.begin[m]);
  m_previous_jac.assign(rows.jac.begin(), rows.jac.begin() + rows.begin[m]);
  m_have_previous_call.value = true;
  // A stored column is its entry's unless its key appears twice (the rows then share one
  // entry, and the first one's column stays in the solve's scratch).
  m_sorted_keys.assign(rows.key.begin(), rows.key.begin() + m);
  std::sort(m_sorted_keys.begin(), m_sorted_keys.end());
  m_previous_from_entries =
      m_derived.empty() && std::adjacent_find(m_sorted_keys.begin(), m_sorted_keys.end()) == m_sorted_keys.end();
}

bool RowColumnCache::repeats_last_call(const RowTable& rows) const {
  const int m = rows.size();
  if (!m_have_previous_call.value || m_previous_keys.size() != static_cast<size_t>(m)) return false;
  const size_t entries = static_cast<size_t>(rows.begin[m]);
  return std::equal(m_previous_keys.begin(), m_previous_keys.end(), rows.key.begin()) &&
         std::equal(m_previous_begin.begin(), m_previous_begin.end(), rows.begin.begin()) &&
         m_previous_nodes.size() == entries &&
         std::equal(m_previous_nodes.begin(), m_previous_nodes.end(), rows.nodes.begin()) &&
         std::equal(m_previous_jac.begin(), m_previous_jac.end(), rows.jac.begin());
}

void RowColumnCache::collect_new_nodes(const RowTable& rows, const std::vector<int>& free_index, int free_dofs,
                                       int node_budget) {
  m_nodes_chosen = true;
  // Kept storage: a warm step allocates only when more nodes hold columns than ever before.
  m_new_nodes.reserve(free_dofs / 3);
  m_nodes.reserve(free_dofs / 3);
  m_derived.reserve(rows.size());
  int energy_rows = 0;
  for (int i = 0; i < rows.size(); ++i) {
    if (rows.kind[i] != RowKind::Energy) continue;
    ++energy_rows;
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
      if (const int f = free_index[rows.nodes[e]]; f >= 0) m_new_nodes.push_back(f);
  }
  std::sort(m_new_nodes.begin(), m_new_nodes.end());
  m_new_nodes.erase(std::unique(m_new_nodes.begin(), m_new_nodes.end()), m_new_nodes.end());
  const double columns = 3.0 * static_cast<double>(m_new_nodes.size());
  if (columns > static_cast<double>(node_budget) * energy_rows || columns * free_dofs > kNodeColumnEntries)
    m_new_nodes.clear();
}

bool RowColumnCache::has_node_columns(const RowTable& rows, const std::vector<int>& free_index, int i) const {
  for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e) {
    const int f = free_index[rows.nodes[e]];
    if (f >= 0 && m_node_slot[f] < 0 &&
        !std::binary_search(m_new_nodes.begin(), m_new_nodes.end(), f))
      return false;
  }
  return true;
}

void RowColumnCache::combine_node_columns(const RowTable& rows, const std::vector<int>& free_index, int free_dofs,
                                          std::vector<const double*>& columns) {
  const int count = static_cast<int>(m_derived.size());
  Eigen::Map<MatX> Y = m_derived_columns.view(free_dofs, count);
  const Eigen::Map<MatX> N = m_node_columns.view(free_dofs, 3 * static_cast<Eigen::Index>(m_nodes.size()));
  // One row per task, its entries summed in stencil order: the same for any thread count.
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& range) {
    for (int k = range.begin(); k < range.end(); ++k) {
      const int i = m_derived[k];
      auto y = Y.col(k);
      y.setZero();
      for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
        if (const int f = free_index[rows.nodes[e]]; f >= 0) y.noalias() += N.middleCols<3>(3 * m_node_slot[f]) * rows.jac[e];
    }
  });
  for (int k = 0; k < count; ++k) columns[m_derived[k]] = Y.col(k).data();
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

void RowColumnCache::store(const RowTable& rows, int i, const double* y, int free_dofs, long generation) {
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
  entry->generation = generation;
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
