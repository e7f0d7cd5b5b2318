#include "engine/assembly/system_pattern.hpp"

#include <algorithm>

namespace sinew {

SystemPattern build_system_pattern(const std::vector<std::array<int, 8>>& element_nodes,
                                   const std::vector<int>& free_index, int num_free) {
  // Free-node adjacency through shared elements (each node is its own neighbour).
  std::vector<std::vector<int>> neighbours(num_free);
  for (const auto& nodes : element_nodes)
    for (int a : nodes)
      for (int b : nodes) {
        if (a < 0 || b < 0) continue;  // a tet's unused slots
        const int fa = free_index[a], fb = free_index[b];
        if (fa >= 0 && fb >= 0) neighbours[fb].push_back(fa);
      }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }

  // Column 3*j+d holds rows 3*i+{0,1,2} for each neighbour i of j, in order.
  const int n = 3 * num_free;
  std::vector<int> outer(n + 1, 0), inner;
  for (int j = 0; j < num_free; ++j)
    for (int d = 0; d < 3; ++d) {
      for (int i : neighbours[j])
        for (int r = 0; r < 3; ++r) inner.push_back(3 * i + r);
      outer[3 * j + d + 1] = static_cast<int>(inner.size());
    }

  SystemPattern pattern;
  pattern.matrix.resize(n, n);
  pattern.matrix.resizeNonZeros(static_cast<int>(inner.size()));
  std::copy(outer.begin(), outer.end(), pattern.matrix.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern.matrix.innerIndexPtr());
  std::fill_n(pattern.matrix.valuePtr(), inner.size(), 0.0);

  auto position = [&](int fi, int fj, int d) {
    const auto& list = neighbours[fj];
    const int k = static_cast<int>(std::lower_bound(list.begin(), list.end(), fi) - list.begin());
    return outer[3 * fj + d] + 3 * k;
  };

  pattern.scatter_begin.assign(1, 0);
  for (const auto& nodes : element_nodes) {
    const int count = static_cast<int>(std::count_if(nodes.begin(), nodes.end(), [](int node) { return node >= 0; }));
    for (int a = 0; a < count; ++a)
      for (int b = 0; b < count; ++b)
        for (int d = 0; d < 3; ++d) {
          const int fa = free_index[nodes[a]], fb = free_index[nodes[b]];
          pattern.element_scatter.push_back((fa >= 0 && fb >= 0) ? position(fa, fb, d) : -1);
        }
    pattern.scatter_begin.push_back(static_cast<int>(pattern.element_scatter.size()));
  }
  pattern.diagonal.resize(n);
  for (int j = 0; j < num_free; ++j)
    for (int d = 0; d < 3; ++d) pattern.diagonal[3 * j + d] = position(j, j, d) + d;
  return pattern;
}

}  // namespace sinew
