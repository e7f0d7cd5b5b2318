#pragma once
// Per node, the elements that hold it and its place in each, by ascending element. A sum of
// per-element terms into nodes (forces, b - A v0, element-by-element products) can then run
// in parallel by node, each node taking its terms in element order: the order of one thread
// looping over the elements, so the same bits for any thread count, and as that loop.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <utility>
#include <vector>

namespace sinew {

struct NodeElements {
  std::vector<int> begin;                    // per node, then the total: entries[begin[n], begin[n + 1])
  std::vector<std::pair<int, int>> entries;  // (element, local node index), ascending element
  // Per element and local node, the index of its entry (-1 for a tet's unused slots): a pass
  // can write an element's per-node terms where sum_by_node then reads them in a row.
  std::vector<std::array<int, 8>> slot;
};

// `element_nodes`: global node indices, -1 in a tet's unused slots.
NodeElements build_node_elements(const std::vector<std::array<int, 8>>& element_nodes, int num_nodes);

// Calls sum(n, first, last) for every node n, in parallel, with [first, last) its entries in
// `incidence`: each node's terms then come in element order, as from one thread looping over
// the elements (the same bits for any thread count). grain: nodes per task (256: the
// creature's 1,000-odd nodes make 3 tasks).
template <typename Sum>
void sum_by_node(const NodeElements& incidence, const Sum& sum, int grain = 256) {
  const int num_nodes = static_cast<int>(incidence.begin.size()) - 1;
  tbb::parallel_for(tbb::blocked_range<int>(0, num_nodes, grain), [&](const tbb::blocked_range<int>& range) {
    for (int n = range.begin(); n != range.end(); ++n) sum(n, incidence.begin[n], incidence.begin[n + 1]);
  });
}

}  // namespace sinew
