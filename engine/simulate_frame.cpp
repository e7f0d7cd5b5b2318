#include "engine/simulate_frame.hpp"

#include <algorithm>

namespace sinew {

FrameStats simulate_frame(World& world, int steps, const std::function<void(int)>& before_step) {
  FrameStats frame;
  std::array<double, kStageCount> ms{};
  std::array<int, kStageCount> skipped{};
  for (int i = 0; i < steps; ++i) {
    if (before_step) before_step(i);
    const bool ok = world.step();
    const StepProfile& p = world.profile();
    frame.step_ms += p.step_ms;
    for (int s = 0; s < kStageCount; ++s) {
      ms[s] += p.ms[s];
      if (!p.skipped[s].empty()) ++skipped[s];
    }
    for (const auto& [kind, n] : p.rows) frame.rows[kind] = std::max(frame.rows[kind], n);
    for (const auto& [solver, n] : p.iterations) frame.iterations[solver] += n;
    for (const auto& [kind, v] : p.violation)
      frame.violation[kind] = frame.violation.count(kind) ? std::max(frame.violation[kind], v) : v;
    if (!ok) {
      frame.finite = false;
      break;
    }
  }
  const StepProfile& last = world.profile();
  for (int s = 0; s < kStageCount; ++s) {
    frame.stages.emplace_back(stage_name(static_cast<Stage>(s)), ms[s]);
    // A stage counts as skipped for the frame when it did no work in any of its steps.
    if (skipped[s] == steps) frame.skipped.emplace_back(stage_name(static_cast<Stage>(s)), last.skipped[s]);
  }
  frame.t = world.state().t;
  frame.kinetic_energy = world.kinetic_energy();
  return frame;
}

}  // namespace sinew
