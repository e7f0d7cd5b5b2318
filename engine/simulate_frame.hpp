#pragma once
// One output frame = several steps of h; their profiles summed into one FrameStats.
#include <functional>

#include "engine/io/stats_writer.hpp"
#include "engine/world.hpp"

namespace sinew {

// Runs `steps` steps. Stops early (finite == false) at the first step that fails.
// `before_step(i)`, if given, runs before step i (the real-time budget sets caps there).
FrameStats simulate_frame(World& world, int steps, const std::function<void(int)>& before_step = {});

}  // namespace sinew
