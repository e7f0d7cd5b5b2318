#pragma once
// Per-stage order statistics over the frames of a run (what `sinew run` prints at the end
// and what the stats JSON's "summary" holds).
#include <string>
#include <vector>

#include "engine/io/stats_writer.hpp"

namespace sinew {

struct StageSummary {
  std::string name;
  double median = 0, p95 = 0, p99 = 0, max = 0, total = 0;  // ms per frame
  int frames_skipped = 0;                                    // frames where the stage did no work
};

// One entry for "step" (the whole frame) followed by one per stage, in first-seen order.
std::vector<StageSummary> summarize_stages(const std::vector<FrameStats>& frames);

// Value at quantile q in [0, 1] (nearest rank) of unsorted samples; 0 for none.
double quantile(std::vector<double> samples, double q);

}  // namespace sinew
