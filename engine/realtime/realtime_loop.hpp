#pragma once
// The fixed-budget real-time loop (issue 7): each frame's steps run with iteration caps
// that fit the frame's simulation budget (BudgetController), and, when paced, frames start
// one frame period apart in wall time. Over-budget frames and the simulated / wall time
// ratio are counted. Reading the wall clock makes this loop non-deterministic; without a
// budget sinew uses the scene's caps (deterministic mode).
#include <chrono>
#include <optional>

#include "engine/realtime/budget_controller.hpp"
#include "engine/simulate_frame.hpp"

namespace sinew {

struct RealtimeSettings {
  double budget_ms = 0;  // simulation time allowed per frame; 0: no budget (the scene's caps)
  bool paced = false;    // wait for each frame's slot (frame period 1 / fps)
  double fps = 60;
};

struct RealtimeCounters {
  int frames = 0;
  int over_budget = 0;    // frames whose steps took longer than the budget
  double simulated_s = 0;
  double wall_s = 0;      // since the first frame started, pacing waits included
  double ratio() const { return wall_s > 0 ? simulated_s / wall_s : 0; }
};

class RealtimeLoop {
 public:
  RealtimeLoop(const SolverDesc& scene, const RealtimeSettings& settings);
  // Runs one frame of `steps` steps (waiting for its slot first when paced).
  FrameStats frame(World& world, int steps);
  const RealtimeCounters& counters() const { return m_counters; }

 private:
  using Clock = std::chrono::steady_clock;
  // How long before a paced frame's slot the threads are woken (worker_warmup.hpp): a
  // sleeping worker took 1.4 ms on average to join, and 2 ms ahead did not always suffice.
  static constexpr std::chrono::milliseconds kWarmupLead{4};
  RealtimeSettings m_settings;
  std::optional<BudgetController> m_budget;
  RealtimeCounters m_counters;
  double m_factorize_ms = 0;  // the last factorisation's time, for the budget's forecast
  Clock::time_point m_start;
};

}  // namespace sinew
