#include "engine/assembly/element_schedule.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>

#include "engine/assembly/for_each_scheduled_element.hpp"

using namespace sinew;

namespace {

// A chain: element e joins nodes e and e + 1 (slots 2-7 unused).
std::vector<std::array<int, 8>> node_chain(int elements) {
  std::vector<std::array<int, 8>> nodes(elements);
  for (int e = 0; e < elements; ++e) nodes[e] = {e, e + 1, -1, -1, -1, -1, -1, -1};
  return nodes;
}

}  // namespace

TEST_CASE("schedule_elements: a chain alternates two colours of consecutive runs") {
  // 640 elements: 640 / 64 = 10 per block, 64 blocks. Block b shares its first node with
  // block b - 1 only, so greedy colouring gives b's colour as b mod 2.
  const ElementSchedule s = schedule_elements(node_chain(640), 641, {{0, 640}});
  REQUIRE(s.colors.size() == 2);
  int scheduled = 0;
  for (const auto& color : s.colors)
    for (const ElementBlock& block : color) scheduled += block.last - block.first;
  CHECK(scheduled == 640);
  for (int k = 0; k < 2; ++k) {
    REQUIRE(s.colors[k].size() == 32);
    for (size_t i = 0; i < s.colors[k].size(); ++i) {
      const int b = 2 * static_cast<int>(i) + k;
      CHECK(s.colors[k][i].first == 10 * b);
      CHECK(s.colors[k][i].last == 10 * b + 10);
    }
  }
}

TEST_CASE("schedule_elements: block length is clamped and blocks never span bodies") {
  // Body 0 has 10 elements (10 / 64 -> the minimum 4: blocks of 4, 4, 2); body 1 has 5000
  // (5000 / 64 = 78 -> the maximum 32). The chain runs through both bodies.
  const ElementSchedule s = schedule_elements(node_chain(5010), 5011, {{0, 10}, {10, 5010}});
  std::vector<ElementBlock> blocks;
  for (const auto& color : s.colors) blocks.insert(blocks.end(), color.begin(), color.end());
  std::sort(blocks.begin(), blocks.end(), [](const ElementBlock& a, const ElementBlock& b) { return a.first < b.first; });
  REQUIRE(blocks.size() == 3 + (5000 + 31) / 32);
  CHECK(blocks[0].first == 0);
  CHECK(blocks[0].last == 4);
  CHECK(blocks[2].first == 8);
  CHECK(blocks[2].last == 10);  // cut at the body's end, not at 12
  for (size_t i = 3; i < blocks.size(); ++i) {
    CHECK(blocks[i].first == 10 + 32 * static_cast<int>(i - 3));
    CHECK(blocks[i].last == std::min(blocks[i].first + 32, 5010));
  }
}

TEST_CASE("schedule_elements: more than 256 blocks on one node is an error") {
  // 257 one-element bodies all holding node 0: each block needs a colour of its own.
  std::vector<std::array<int, 8>> nodes(257, {0, -1, -1, -1, -1, -1, -1, -1});
  std::vector<std::pair<int, int>> bodies;
  for (int e = 0; e < 257; ++e) bodies.emplace_back(e, e + 1);
  CHECK_THROWS_AS(schedule_elements(nodes, 1, bodies), std::runtime_error);
  bodies.pop_back();
  nodes.pop_back();
  CHECK(schedule_elements(nodes, 1, bodies).colors.size() == 256);
}

TEST_CASE("for_each_scheduled_element: visits each element once, in index order within a block") {
  const std::vector<std::array<int, 8>> nodes = node_chain(1000);
  const ElementSchedule s = schedule_elements(nodes, 1001, {{0, 1000}});
  // Per element, the number of visits; per node, the elements that touched it in order: a
  // colour's blocks share no node, so the writes below never race.
  std::vector<int> visits(1000, 0);
  std::vector<std::vector<int>> touched(1001);
  for_each_scheduled_element(s, [&](int e) {
    ++visits[e];
    for (int a = 0; a < 2; ++a) touched[nodes[e][a]].push_back(e);
  });
  for (int v : visits) CHECK(v == 1);
  // Node n inside a block is touched by e = n - 1 then e = n (same block, index order).
  for (const auto& color : s.colors)
    for (const ElementBlock& block : color)
      for (int n = block.first + 1; n < block.last; ++n) CHECK(touched[n] == std::vector<int>{n - 1, n});
}
