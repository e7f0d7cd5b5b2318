#include "engine/realtime/realtime_loop.hpp"

#include <thread>

#include "engine/realtime/worker_warmup.hpp"
#include "engine/step/stages.hpp"

namespace sinew {

RealtimeLoop::RealtimeLoop(const SolverDesc& scene, const RealtimeSettings& settings) : m_settings(settings) {
  if (settings.budget_ms > 0) m_budget.emplace(scene, settings.budget_ms);
}

FrameStats RealtimeLoop::frame(World& world, int steps) {
  if (m_counters.frames == 0) m_start = Clock::now();
  // Paced: sleep until kWarmupLead before the frame's slot, then keep every thread awake
  // until it (worker_warmup.hpp).
  if (m_settings.paced) {
    const auto slot = m_start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(m_counters.frames / m_settings.fps));
    std::this_thread::sleep_until(slot - kWarmupLead);
    keep_threads_awake_until(slot);
  }
  const auto frame_start = Clock::now();
  FrameStats stats = simulate_frame(world, steps, [&](int i) {
    if (!m_budget) {
      world.mutable_state().caps = {};
      return;
    }
    const double elapsed = std::chrono::duration<double, std::milli>(Clock::now() - frame_start).count();
    const StepProfile& last = world.profile();
    const bool linear = !world.model().has_hyperelastic;  // Newton's factorisations are its own
    if (linear && last.step_ms > 0 && last.ran(Stage::Factorize))
      m_factorize_ms = last.ms[static_cast<int>(Stage::Factorize)];
    FactorisationForecast next;
    // A change of the sleeping set forces a factorisation the rule cannot see.
    next.known = linear && !world.state().sleep.changed;
    next.factorises = !reuses_factorisation(world.model(), world.uses_cholmod(), world.state());
    next.factorize_ms = m_factorize_ms;
    world.mutable_state().caps = m_budget->caps(elapsed, steps - i, last, next);
  });
  const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - frame_start).count();
  ++m_counters.frames;
  if (m_budget && frame_ms > m_budget->budget_ms()) ++m_counters.over_budget;
  m_counters.simulated_s += world.model().h * steps;
  m_counters.wall_s = std::chrono::duration<double>(Clock::now() - m_start).count();
  return stats;
}

}  // namespace sinew
