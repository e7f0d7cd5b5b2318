#pragma once
// Per node, the elements that hold it and its place in each, by ascending element. A sum of
// per-element terms into nodes (forces, b - A v0, element-by-element products) can then run
// in parallel by node, each node taking its terms in element order: the order of one thread
// looping over the elements, so the same bits for any thread count, and as that loop.
#include <array>
#include <utility>
#include <vector>

namespace sinew {

struct NodeElements {
  std::vector<int> begin;                    // per node, then the total: entries[begin[n], begin[n + 1])
  std::vector<std::pair<int, int>> entries;  // (element, local node index), ascending element
};

// `element_nodes`: global node indices, -1 in a tet's unused slots.
NodeElements build_node_elements(const std::vector<std::array<int, 8>>& element_nodes, int num_nodes);

}  // namespace sinew
