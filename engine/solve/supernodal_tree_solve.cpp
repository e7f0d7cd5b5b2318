#include "engine/solve/supernodal_tree_solve.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <numeric>

#include "engine/solve/supernode_view.hpp"
#include "engine/solve/tree_kernels.hpp"

namespace sinew {

void SupernodalTreeSolve::analyse(const cholmod_factor& L) {
  m_factor = &L;
  m_n = static_cast<int>(L.n);
  m_usable = m_ordered = false;
  for (auto& bin : m_bins) bin.clear();
  m_top.clear();
  m_top_rows.clear();
  m_widest_top = 0;
  if (!L.is_super || !L.is_ll || L.itype != CHOLMOD_INT || L.xtype != CHOLMOD_REAL) return;
  const int count = static_cast<int>(L.nsuper);
  const int* super = static_cast<const int*>(L.super);
  std::vector<int> supernode_of(m_n), parent(count, -1), first(count);
  for (int s = 0; s < count; ++s)
    for (int k = super[s]; k < super[s + 1]; ++k) supernode_of[k] = s;
  std::vector<long> cost(count), subtree(count);
  std::vector<int> size(count, 1);
  std::vector<std::vector<int>> children(count);
  m_max_below = 0;
  for (int s = 0; s < count; ++s) {
    const SupernodeView sn = supernode_view(L, s);
    cost[s] = static_cast<long>(sn.columns) * sn.height;
    m_max_below = std::max(m_max_below, sn.height - sn.columns);
    if (sn.height > sn.columns) parent[s] = supernode_of[sn.rows[sn.columns]];
  }
  // Subtree work and extent; CHOLMOD postorders its tree, so a subtree is the range
  // first[s]..s (checked: without it there is no split).
  for (int s = 0; s < count; ++s) first[s] = s, subtree[s] = cost[s];
  std::vector<int> roots;
  for (int s = 0; s < count; ++s) {
    const int p = parent[s];
    if (p < 0) {
      roots.push_back(s);
      continue;
    }
    if (p <= s) return;
    children[p].push_back(s);
    subtree[p] += subtree[s];
    size[p] += size[s];
    first[p] = std::min(first[p], first[s]);
  }
  // Every parent after its children: the supernodes in their own order solve on one thread.
  m_ordered = true;
  m_y.assign(m_n, 0.0);
  m_gather[0].assign(std::max(1, m_max_below), 0.0);
  for (int s = 0; s < count; ++s)
    if (size[s] != s - first[s] + 1) return;
  const long total = std::accumulate(cost.begin(), cost.end(), 0L);
  // Expand the heaviest subtree into its root (to the top) and its children until the two
  // bins, filled heaviest first, balance; keep the cheapest estimate top + max(bin) seen.
  std::vector<int> candidates = roots, best_candidates;
  long top_work = 0, best_estimate = total + 1;
  const auto heavier = [&](int a, int b) { return subtree[a] != subtree[b] ? subtree[a] > subtree[b] : a < b; };
  for (int expansion = 0; expansion < 512 && !candidates.empty(); ++expansion) {
    std::sort(candidates.begin(), candidates.end(), heavier);
    std::array<long, 2> load{};
    for (const int c : candidates) load[load[1] < load[0]] += subtree[c];
    if (const long estimate = top_work + std::max(load[0], load[1]); estimate < best_estimate) {
      best_estimate = estimate;
      best_candidates = candidates;
    }
    const int heaviest = candidates.front();
    if (top_work + cost[heaviest] > total / 2) break;
    top_work += cost[heaviest];
    candidates.erase(candidates.begin());
    candidates.insert(candidates.end(), children[heaviest].begin(), children[heaviest].end());
  }
  // Worth two threads only if it takes a quarter off the single-thread work.
  if (best_estimate > 3 * total / 4) return;
  std::vector<char> in_bin(count, 0);
  m_bin_entries = {0, 0};
  for (const int c : best_candidates) {
    const int b = m_bin_entries[1] < m_bin_entries[0];
    m_bin_entries[b] += subtree[c];
    m_bins[b].push_back({first[c], c});
    std::fill(in_bin.begin() + first[c], in_bin.begin() + c + 1, 1);
  }
  for (auto& bin : m_bins)
    std::sort(bin.begin(), bin.end(), [](const Range& a, const Range& b) { return a.first < b.first; });
  m_top_entries = 0;
  for (int s = 0; s < count; ++s) {
    if (in_bin[s]) continue;
    m_top.push_back(s);
    m_top_entries += cost[s];
    m_widest_top = std::max(m_widest_top, super[s + 1] - super[s]);
    if (WideSupernodePasses::worth_two_threads(super[s + 1] - super[s])) m_wide.reserve(super[s + 1] - super[s]);
    for (int k = super[s]; k < super[s + 1]; ++k) m_top_rows.push_back(k);
  }
  for (int b = 0; b < 2; ++b) {
    m_bin_y[b].assign(m_n, 0.0);
    m_gather[b].assign(std::max(1, m_max_below), 0.0);
  }
  m_usable = true;
}

void SupernodalTreeSolve::solve(const cholmod_factor& L, const double* b, double* x) {
  solve_with(L, static_cast<const double*>(L.x), b, x);
}

void SupernodalTreeSolve::solve(const cholmod_factor& L, const float* values, const double* b, double* x) {
  solve_with(L, values, b, x);
}

template <class Real>
void SupernodalTreeSolve::solve_with(const cholmod_factor& L, const Real* values, const double* b, double* x) {
  const int* perm = static_cast<const int*>(L.Perm);
  const int* super = static_cast<const int*>(L.super);
  const auto view = [&](int s) { return supernode_view(L, s, values); };
  double* y = m_y.data();
  for (int k = 0; k < m_n; ++k) y[k] = b[perm[k]];
  if (!m_usable) {  // no split: every supernode in order, on this thread
    const int count = static_cast<int>(L.nsuper);
    for (int s = 0; s < count; ++s) tree_forward(view(s), y, m_gather[0].data());
    for (int s = count - 1; s >= 0; --s) tree_backward(view(s), y, m_gather[0].data());
    for (int k = 0; k < m_n; ++k) x[perm[k]] = y[k];
    return;
  }
  // Forward in the bins, each on its own copy: its rows from y, the top rows zero (they
  // collect the bin's updates).
  const auto bin_forward = [&](int bin) {
    double* own = m_bin_y[bin].data();
    for (const int k : m_top_rows) own[k] = 0;
    for (const Range& range : m_bins[bin]) {
      std::copy(y + super[range.first], y + super[range.last + 1], own + super[range.first]);
      for (int s = range.first; s <= range.last; ++s) tree_forward(view(s), own, m_gather[bin].data());
      std::copy(own + super[range.first], own + super[range.last + 1], y + super[range.first]);
    }
  };
  tbb::parallel_invoke([&] { bin_forward(0); }, [&] { bin_forward(1); });
  for (const int k : m_top_rows) y[k] = (y[k] + m_bin_y[0][k]) + m_bin_y[1][k];
  // The top: its wide supernodes (the root) on both threads, the others on this one.
  for (const int s : m_top) m_wide.forward(view(s), y, m_gather[0].data());
  for (auto s = m_top.rbegin(); s != m_top.rend(); ++s) m_wide.backward(view(*s), y, m_gather[0].data());
  const auto bin_backward = [&](int bin) {
    const auto& ranges = m_bins[bin];
    for (auto range = ranges.rbegin(); range != ranges.rend(); ++range)
      for (int s = range->last; s >= range->first; --s) tree_backward(view(s), y, m_gather[bin].data());
  };
  tbb::parallel_invoke([&] { bin_backward(0); }, [&] { bin_backward(1); });
  for (int k = 0; k < m_n; ++k) x[perm[k]] = y[k];
}

}  // namespace sinew

