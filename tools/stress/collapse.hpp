#pragma once
// Case collapse_U50: paper 000, fig. 5, the 117-hex sphere of E 50 kPa collapsing on the
// ground with a 50 J energy limit per element (assets/scenes/paper000_collapse_50kPa_U50.json),
// run twice as long as the scene (the full run) so that it settles. Every step must be solved,
// finite; the worst element volume loss and the limit's and contact's worst violations are
// reported (the volume bound the limit implies is asserted by test_paper000_collapse.cpp).
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

inline CaseResult run_collapse(const Options& options) {
  const SceneDesc scene = shipped_scene("paper000_collapse_50kPa_U50");
  const int steps = (options.quick ? 1 : 2) * scene.frames * scene.steps_per_frame();
  World world = make_world(scene);
  const double top_rest = surface_y_range(world, 0).second;
  double J_min = 1e300, top_min = 1e300;
  const RunOutcome run = run_steps(world, steps, [&](int) {
    J_min = std::min(J_min, volume_ratio_range(world).first);
    top_min = std::min(top_min, surface_y_range(world, 0).second);
  });
  const auto energy = run.worst_violation.find("energy");
  const auto penetration = run.worst_violation.find("penetration");
  const double worst_energy = energy == run.worst_violation.end() ? 0 : energy->second;
  const double worst_penetration = penetration == run.worst_violation.end() ? 0 : penetration->second;
  CaseResult r;
  r.pass = run.completed();
  r.summary = format("%s of %d, finite; worst element volume loss %.1f %%, top sank to %.0f %% of its rest "
                     "height, worst Ue/Umax - 1 %.3g, worst penetration %.3g m",
                     describe(run).c_str(), steps, 100 * (1 - J_min), 100 * top_min / top_rest, worst_energy,
                     worst_penetration);
  r.details = to_json(run);
  r.details["planned_steps"] = steps;
  r.details["worst_element_volume_loss"] = 1 - J_min;
  r.details["lowest_top_over_rest_top"] = top_min / top_rest;
  return r;
}

}  // namespace sinew::stress
