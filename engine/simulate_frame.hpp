#pragma once
// One output frame = several steps of h; their profiles summed into one FrameStats.
#include "engine/io/stats_writer.hpp"
#include "engine/world.hpp"

namespace sinew {

// Runs `steps` steps. Stops early (finite == false) at the first step that fails.
FrameStats simulate_frame(World& world, int steps);

}  // namespace sinew
