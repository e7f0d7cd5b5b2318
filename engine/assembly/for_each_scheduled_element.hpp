#pragma once
// The parallel loop over an ElementSchedule (element_schedule.hpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/assembly/element_schedule.hpp"

namespace sinew {

// Calls visit(e) for every element of the schedule: colours in turn, a colour's blocks in
// parallel (oneTBB), each block's elements in index order.
template <class Visit>
void for_each_scheduled_element(const ElementSchedule& schedule, const Visit& visit) {
  for (const std::vector<ElementBlock>& color : schedule.colors)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, color.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t b = range.begin(); b != range.end(); ++b)
        for (int e = color[b].first; e < color[b].last; ++e) visit(e);
    });
}

}  // namespace sinew
