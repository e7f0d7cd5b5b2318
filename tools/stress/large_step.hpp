#pragma once
// Case large_step: the beam and creature scenes with h = 1/10 s instead of 1/60 s, over the
// scene's simulated duration (frames / fps). Backward Euler is unconditionally stable, so
// every step must be solved and the state stay finite; the constraint violations reached
// are reported (large steps make the limits and contacts harder to meet within the SQP cap).
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

inline CaseResult run_large_step(const Options& options) {
  constexpr double kH = 0.1;  // s
  const std::vector<std::string> names =
      options.quick ? std::vector<std::string>{"paper000_beam_150kPa_U0.5", "paper001_beam_5kPa_isotropic",
                                               "paper000_creature_500kPa_U100"}
                    : std::vector<std::string>{"paper000_beam_150kPa", "paper000_beam_150kPa_U0.1",
                                               "paper000_beam_150kPa_U0.5", "paper000_beam_150kPa_U1.0",
                                               "paper000_beam_2MPa", "paper001_beam_200kPa",
                                               "paper001_beam_5kPa_anisotropic", "paper001_beam_5kPa_isotropic",
                                               "paper000_creature_500kPa", "paper000_creature_500kPa_U100",
                                               "paper000_creature_5MPa"};
  CaseResult r;
  r.details["h"] = kH;
  r.details["scenes"] = nlohmann::json::array();
  int completed = 0;
  std::map<std::string, double> worst;
  for (const std::string& name : names) {
    const auto start = std::chrono::steady_clock::now();
    SceneDesc scene = shipped_scene(name);
    const double duration = scene.frames / scene.fps;
    scene.h = kH;
    World world = make_world(scene);
    const RunOutcome run = run_steps(world, int(std::lround(duration / kH)));
    completed += run.completed();
    std::string violations;
    for (const auto& [kind, value] : run.worst_violation) {
      if (!has_constraint_kind(world.model(), kind)) continue;
      worst[kind] = std::max(worst[kind], value);
      violations += format(", worst %s %.3g", kind.c_str(), value);
    }
    const double seconds = seconds_since(start);
    std::printf("  %-34s %s%s%s (%.1f s)\n", name.c_str(), run.completed() ? "" : "FAIL: ", describe(run).c_str(),
                violations.c_str(), seconds);
    std::fflush(stdout);
    nlohmann::json entry = to_json(run);
    entry["scene"] = name;
    entry["seconds"] = seconds;
    r.details["scenes"].push_back(entry);
  }
  r.pass = completed == int(names.size());
  std::string violations;
  for (const auto& [kind, value] : worst) violations += format(", worst %s %.3g", kind.c_str(), value);
  r.summary = format("%d/%zu scenes at h = 0.1 s ran to the end finite with no step refused", completed,
                     names.size()) +
              violations + " (energy: Ue/Umax - 1; strain: stretch past the limit; penetration: m)";
  return r;
}

}  // namespace sinew::stress
