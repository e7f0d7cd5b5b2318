#include "tools/scale_sweep/measure.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "engine/realtime/worker_warmup.hpp"
#include "engine/scene/scene.hpp"
#include "engine/simulate_frame.hpp"
#include "engine/world.hpp"

namespace sinew::sweep {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string format(const char* fmt, auto... args) {
  std::string out(std::snprintf(nullptr, 0, fmt, args...), '\0');
  std::snprintf(out.data(), out.size() + 1, fmt, args...);
  return out;
}

// One step of each World, each under its own thread limit; returns the round's wall time.
// `timed` keeps the steps' profiles. A World whose step is refused stops there. Before a
// timed step on several threads, the workers are kept spinning for kWarmup: through the
// other Worlds' steps (seconds at 10k hex) they fell asleep, and a sleeping worker took 1.4
// ms on average to join a parallel loop on the 2-core VM (engine/realtime/worker_warmup.hpp),
// which made stage 1 look slower on 2 threads than on 1 (2,662 hex: 1.81 -> 2.15 ms; with
// the warm-up 2.21 -> 0.98 ms). Steps run one after another, as a simulation runs, find
// them awake. (Once, sizes 1000,3000,10000 in one run, stage 1 at 9,826 hex measured
// slower on 2 threads, 11.4 -> 18.8 ms; run alone later, 7.27 -> 4.20 ms: not understood.)
double step_round(std::vector<std::unique_ptr<World>>& worlds, std::vector<ThreadRun>& runs, bool timed) {
  constexpr auto kWarmup = std::chrono::milliseconds(5);
  const auto start = Clock::now();
  for (size_t i = 0; i < worlds.size(); ++i) {
    if (!runs[i].finite) continue;
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, runs[i].threads);
    if (timed) {
      if (runs[i].threads > 1) keep_threads_awake_until(Clock::now() + kWarmup);
      runs[i].samples.push_back(simulate_frame(*worlds[i], 1));
      runs[i].finite = runs[i].samples.back().finite;
    } else {
      runs[i].finite = worlds[i]->step();
    }
  }
  return seconds_since(start);
}

std::string round_line(const std::vector<ThreadRun>& runs) {
  std::string line;
  for (const ThreadRun& r : runs)
    line += format("%s%d thread%s %.1f ms", line.empty() ? "" : ", ", r.threads, r.threads == 1 ? "" : "s",
                   r.samples.empty() ? 0.0 : r.samples.back().step_ms);
  return line;
}

}  // namespace

bool SizeResult::hashes_equal() const {
  return std::all_of(runs.begin(), runs.end(), [&](const ThreadRun& r) { return r.state_hash == runs[0].state_hash; });
}

int timed_step_count(int steps, double budget, double round_seconds) {
  if (round_seconds <= 0 || steps * round_seconds <= budget) return steps;
  return std::clamp(static_cast<int>(budget / round_seconds), std::min(steps, 3), steps);
}

SizeResult measure_size(int target, const SweepOptions& options,
                        const std::function<void(const std::string&)>& progress) {
  SizeResult r;
  r.target = target;
  r.dims = lattice_for(target, options.block);
  r.scene_text = lattice_scene_text(r.dims, options.block);
  const SceneDesc scene = parse_scene_text(r.scene_text, "scale sweep block", SINEW_SOURCE_DIR);

  std::vector<std::unique_ptr<World>> worlds;
  for (int threads : options.threads) {
    const auto start = Clock::now();
    worlds.push_back(std::make_unique<World>(build_model(scene, [](const std::string&) {}), initial_velocities(scene)));
    if (worlds.size() == 1) r.build_seconds = seconds_since(start);
    r.runs.push_back({threads, {}, true, 0});
  }
  const Model& model = worlds[0]->model();
  r.elements = model.num_elements;
  r.nodes = model.num_nodes;
  r.dofs = 3 * model.num_free;
  for (const auto& surface : worlds[0]->state().surface) r.surface_vertices += static_cast<int>(surface.size());
  progress(format("%d hex (%d x %d x %d cells of %.4g m), %d DOFs, %d surface vertices; built in %.1f s", r.elements,
                  r.dims.nx, r.dims.ny, r.dims.nz, r.dims.cell_size, r.dofs, r.surface_vertices, r.build_seconds));

  double round_seconds = 0;
  for (int i = 0; i < options.warmup; ++i) {
    round_seconds = step_round(worlds, r.runs, false);
    if (round_seconds > 2 || i + 1 == options.warmup)
      progress(format("warm-up %d/%d: %.1f s for one step of each thread count", i + 1, options.warmup, round_seconds));
  }
  r.warmup = options.warmup;
  r.steps = timed_step_count(options.steps, options.budget, round_seconds);
  if (r.steps < options.steps)
    progress(format("%d timed steps instead of %d (a round takes %.1f s; budget %.0f s)", r.steps, options.steps,
                    round_seconds, options.budget));

  const int every = std::max(1, r.steps / 4);
  for (int i = 0; i < r.steps; ++i) {
    const double seconds = step_round(worlds, r.runs, true);
    if (seconds > 2 || (i + 1) % every == 0 || i + 1 == r.steps)
      progress(format("step %d/%d: %s", i + 1, r.steps, round_line(r.runs).c_str()));
  }
  for (size_t i = 0; i < worlds.size(); ++i) {
    r.runs[i].state_hash = worlds[i]->state_hash();
    if (!r.runs[i].finite) progress(format("%d threads: a step was refused (non-finite or singular)", r.runs[i].threads));
  }
  return r;
}

}  // namespace sinew::sweep
