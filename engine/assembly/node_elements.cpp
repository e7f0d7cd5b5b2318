#include "engine/assembly/node_elements.hpp"

namespace sinew {

NodeElements build_node_elements(const std::vector<std::array<int, 8>>& element_nodes, int num_nodes) {
  NodeElements out;
  out.begin.assign(num_nodes + 1, 0);
  for (const auto& nodes : element_nodes)
    for (int n : nodes)
      if (n >= 0) ++out.begin[n + 1];
  for (int n = 0; n < num_nodes; ++n) out.begin[n + 1] += out.begin[n];
  out.entries.resize(out.begin[num_nodes]);
  std::vector<int> next(out.begin.begin(), out.begin.end() - 1);
  out.slot.assign(element_nodes.size(), std::array<int, 8>{-1, -1, -1, -1, -1, -1, -1, -1});
  // Elements in ascending order: each node's list comes out sorted.
  for (int e = 0; e < static_cast<int>(element_nodes.size()); ++e)
    for (int a = 0; a < 8; ++a)
      if (const int n = element_nodes[e][a]; n >= 0) {
        out.slot[e][a] = next[n];
        out.entries[next[n]++] = {e, a};
      }
  return out;
}

}  // namespace sinew
