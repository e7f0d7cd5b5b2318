#pragma once
// The parallel loop over an ElementSchedule (element_schedule.hpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

// Calls visit(e) for every element of the schedule, each block's in index order.
template <class Visit>
void for_each_scheduled_element(const ElementSchedule& schedule, const Visit& visit) {
  for_each_scheduled_block(schedule, [&](int first, int last) {
    for (int e = first; e < last; ++e) visit(e);
  });
}

}  // namespace sinew
