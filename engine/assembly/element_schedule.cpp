#include "engine/assembly/element_schedule.hpp"

#include <algorithm>
#include <bitset>
#include <stdexcept>

namespace sinew {

namespace {

// Long enough for memory-order reads (a block of 8 tets streams 6 kB of scatter maps), short
// enough that a body of a few hundred elements still gives each colour several blocks for the
// threads to share: count / 64, clamped to [4, 32].
int elements_per_block(int count) { return std::clamp(count / 64, 4, 32); }

}  // namespace

ElementSchedule schedule_elements(const std::vector<std::array<int, 8>>& element_nodes, int num_nodes,
                                  const std::vector<std::pair<int, int>>& bodies, int block_size) {
  constexpr int kMaxColors = 256;
  std::vector<std::bitset<kMaxColors>> used(num_nodes);
  ElementSchedule schedule;
  for (const auto& [first, last] : bodies) {
    const int size = block_size > 0 ? block_size : elements_per_block(last - first);
    for (int begin = first; begin < last; begin += size) {
      const ElementBlock block{begin, std::min(begin + size, last)};
      std::bitset<kMaxColors> taken;
      for (int e = block.first; e < block.last; ++e)
        for (int n : element_nodes[e])
          if (n >= 0) taken |= used[n];
      int k = 0;
      while (k < kMaxColors && taken[k]) ++k;
      if (k == kMaxColors) throw std::runtime_error("element schedule: a node is shared by too many element blocks");
      for (int e = block.first; e < block.last; ++e)
        for (int n : element_nodes[e])
          if (n >= 0) used[n].set(k);
      if (k >= static_cast<int>(schedule.colors.size())) schedule.colors.resize(k + 1);
      schedule.colors[k].push_back(block);
    }
  }
  return schedule;
}

}  // namespace sinew
