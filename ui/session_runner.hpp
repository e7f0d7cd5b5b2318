#pragma once
// Runs a session script: the scene frame by frame, drawn off-screen with the panel, the
// script's events fed in as synthetic input at their frames, expectations checked.
// Deterministic: every decision follows the frame count, never the wall clock, so the same
// script gives the same frames and the same final state hash.
#include <cstdint>
#include <map>
#include <ostream>
#include <string>

#include "ui/session_script.hpp"

namespace sinew {

struct SessionOptions {
  std::string record_path;  // --record: the video of the whole session ("" = none)
  int threads = 0;          // 0: all cores
  bool progress = true;     // progress lines on stderr
};

struct SessionResult {
  int frames = 0;            // frames run (the last one included)
  int expectations = 0;      // checked
  int failed = 0;            // of those, not met
  bool finite = true;        // false: a step failed (NaN/Inf or divergence) and the run stopped
  uint64_t state_hash = 0;   // World::state_hash() at the end
  std::map<std::string, double> measured;  // each expectation's value, by its event path
};

// Throws InputError for a script that cannot run (unknown widget, parameter or body,
// nothing under a grab pixel...), naming the event's JSON path.
SessionResult run_session(const SessionScript& script, const SessionOptions& options, std::ostream& log);

}  // namespace sinew
