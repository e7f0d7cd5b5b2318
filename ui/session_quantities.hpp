#pragma once
// The quantities an "expect" event compares (docs/sessions.md): solver statistics of the
// last frame, parameters, body bounds and centroids, the grab's distance from its target.
#include <optional>
#include <string>

#include "engine/io/stats_writer.hpp"
#include "ui/live_scene.hpp"

namespace sinew {

struct SessionSnapshot {
  const LiveScene& live;
  const FrameStats& frame;             // the last simulated frame
  const Attachment* grab = nullptr;    // the current grab, if any
};

// Throws InputError("...") for an unknown quantity; `what` is the event's path for messages.
double session_quantity(const std::string& quantity, const SessionSnapshot& snapshot, const std::string& what);

}  // namespace sinew
