#pragma once
// The parallel loop over an ElementSchedule (element_schedule.hpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

#include "engine/assembly/element_schedule.hpp"

namespace sinew {

// Calls visit_block(first, last) for every block of the schedule: colours in turn, a
// colour's blocks in parallel (oneTBB); the visit takes the block's elements in index order.
template <class VisitBlock>
void for_each_scheduled_block(const ElementSchedule& schedule, const VisitBlock& visit_block) {
  for (const std::vector<ElementBlock>& color : schedule.colors)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, color.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t b = range.begin(); b != range.end(); ++b) visit_block(color[b].first, color[b].last);
    });
}

// Calls visit_block(first, last) for every block of the schedule, all colours at once: for
// loops whose visits write per-element results only (nothing shared between elements), which
// need no colour-by-colour barrier (bunny_5: 21 colours, 21 fork-joins).
template <class VisitBlock>
void for_each_scheduled_block_at_once(const ElementSchedule& schedule, const VisitBlock& visit_block) {
  // One loop over the blocks of every colour (a nested loop per colour cost more than the
  // visits of bunny_5's 5,266 tets): block i of the whole is found in the colours' offsets.
  std::array<size_t, 257> offsets;  // at most 256 colours (schedule_elements)
  const size_t colors = schedule.colors.size();
  offsets[0] = 0;
  for (size_t c = 0; c < colors; ++c) offsets[c + 1] = offsets[c] + schedule.colors[c].size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, offsets[colors], 1), [&](const tbb::blocked_range<size_t>& range) {
    size_t c = std::upper_bound(offsets.begin(), offsets.begin() + colors + 1, range.begin()) - offsets.begin() - 1;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      while (i >= offsets[c + 1]) ++c;
      const ElementBlock& block = schedule.colors[c][i - offsets[c]];
      visit_block(block.first, block.last);
    }
  });
}

// Calls visit(e) for every element of the schedule, each block's in index order.
template <class Visit>
void for_each_scheduled_element(const ElementSchedule& schedule, const Visit& visit) {
  for_each_scheduled_block(schedule, [&](int first, int last) {
    for (int e = first; e < last; ++e) visit(e);
  });
}

}  // namespace sinew
