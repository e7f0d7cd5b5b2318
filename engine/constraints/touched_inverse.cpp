#include "engine/constraints/touched_inverse.hpp"

#include <atomic>

namespace sinew {

namespace {

// Versions from one counter for every instance: equal versions mean the same G, even in a
// copy (a per-instance count could meet another instance's at a different G).
long next_version() {
  static std::atomic<long> counter{0};
  return ++counter;
}

}  // namespace

void TouchedInverse::reset(int free_nodes) {
  m_stale = false;
  m_version = next_version();
  for (const int f : m_nodes) m_local[f] = -1;
  m_local.resize(free_nodes, -1);
  m_nodes.clear();
  m_rows.reserve(3 * static_cast<size_t>(free_nodes));  // require's wanted rows: no allocation later
}

void TouchedInverse::grow(int nodes) {
  if (3 * nodes <= m_G.rows()) return;
  int capacity = std::max<int>(16, static_cast<int>(m_G.rows()) / 3);
  while (capacity < nodes) capacity *= 2;
  capacity = std::min<int>(capacity, static_cast<int>(m_local.size()));
  MatX grown(3 * capacity, 3 * capacity);
  const int k = 3 * size();
  grown.topLeftCorner(k, k) = m_G.topLeftCorner(k, k);
  m_G.swap(grown);
}

// X = H^-1 on the added nodes' DOFs: its rows at every touched node give G's new columns
// and, by symmetry, its new rows. The new-new block is averaged with its transpose so that
// G is exactly symmetric (round-off in the solves is not).
void TouchedInverse::add_columns(const std::vector<int>& added, const Eigen::Ref<const MatX>& X) {
  m_version = next_version();
  const int old = size();
  grow(old + static_cast<int>(added.size()));
  m_nodes.insert(m_nodes.end(), added.begin(), added.end());
  const int k = 3 * size();
  for (int a = 0; a < size(); ++a) {
    const int row = 3 * m_nodes[a];
    for (int c = 0; c < static_cast<int>(X.cols()); ++c)
      m_G.block<3, 1>(3 * a, 3 * old + c) = X.block<3, 1>(row, c);
  }
  const int k_old = 3 * old;
  const int k_new = k - k_old;
  m_G.block(k_old, 0, k_new, k_old) = m_G.block(0, k_old, k_old, k_new).transpose();
  for (int c = k_old; c < k; ++c)
    for (int r = c + 1; r < k; ++r) m_G(r, c) = m_G(c, r) = 0.5 * (m_G(r, c) + m_G(c, r));
}

}  // namespace sinew
