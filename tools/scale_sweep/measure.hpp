#pragma once
// Timing one size of the scale sweep: the same scene stepped by one World per thread count,
// interleaved step by step (so that a change of machine load during the run hits every
// thread count alike), after the same warm-up. The engine's results do not depend on the
// thread count, so every World takes exactly the same steps: the state hashes are compared
// at the end.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/io/stats_writer.hpp"
#include "tools/scale_sweep/lattice_scene.hpp"

namespace sinew::sweep {

struct SweepOptions {
  std::vector<int> sizes{100, 300, 1000, 3000, 10000, 20000};  // target cell counts
  int steps = 30;       // timed steps per size and thread count, at most
  int warmup = 10;      // untimed steps first (the start of the sag under gravity)
  double budget = 120;  // s of timed stepping per size (all thread counts) before fewer steps
  std::vector<int> threads{1, 2};
  RestingBlock block;  // the scene's parameters (energy_density_limit is an option)
  bool quick = false;
};

struct ThreadRun {
  int threads = 1;
  std::vector<FrameStats> samples;  // one per timed step
  bool finite = true;               // no step was refused
  uint64_t state_hash = 0;          // after the last step
};

struct SizeResult {
  int target = 0;
  LatticeDims dims;
  std::string scene_text;
  int elements = 0, nodes = 0, dofs = 0, surface_vertices = 0;
  double build_seconds = 0;  // build_model of one World
  int warmup = 0, steps = 0;  // steps = timed steps actually taken
  std::vector<ThreadRun> runs;  // in the order of SweepOptions::threads
  bool hashes_equal() const;
};

// Timed steps for a size: all of `steps` when one round of warm-up steps (every thread
// count once) took `round_seconds` and they fit in `budget`; else as many as fit, but at
// least min(steps, 3).
int timed_step_count(int steps, double budget, double round_seconds);

// Builds, warms up and times one size. `progress` receives one line at a time.
SizeResult measure_size(int target, const SweepOptions& options,
                        const std::function<void(const std::string&)>& progress);

}  // namespace sinew::sweep
