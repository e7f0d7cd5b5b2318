#pragma once
// Checks the contract of a model's element schedule (engine/assembly/element_schedule.hpp):
// every element in exactly one block, a block a run of one body's elements, and no node
// shared by two blocks of one colour.
#include <doctest/doctest.h>

#include <vector>

#include "engine/model.hpp"

namespace sinew {

inline void check_element_schedule(const Model& m, bool all_elements = true) {
  std::vector<int> scheduled(m.num_elements, 0);
  for (const auto& color : m.element_schedule.colors) {
    std::vector<int> owner(m.num_nodes, -1);  // the block of this colour that touched the node
    for (size_t b = 0; b < color.size(); ++b) {
      const ElementBlock& block = color[b];
      REQUIRE(0 <= block.first);
      REQUIRE(block.first < block.last);
      REQUIRE(block.last <= m.num_elements);
      CHECK(m.element_body[block.first] == m.element_body[block.last - 1]);
      for (int e = block.first; e < block.last; ++e) {
        ++scheduled[e];
        for (int n : m.element_nodes[e]) {
          if (n < 0) continue;
          CHECK((owner[n] == -1 || owner[n] == static_cast<int>(b)));
          owner[n] = static_cast<int>(b);
        }
      }
    }
  }
  if (!all_elements) return;
  for (int e = 0; e < m.num_elements; ++e) CHECK(scheduled[e] == 1);
}

}  // namespace sinew
