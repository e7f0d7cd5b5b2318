#pragma once
// Case crush_release: a 0.5 m ball resting on the ground is crushed to a tenth of its height
// by a kinematic plate (a downward-facing plane, docs/scenes.md "motion") in 1 s, held for
// 0.5 s, then the plate is pulled away in 0.1 s and the ball released. Linear corotational
// (hex), the same with a 1 J energy limit per element (full run only: the limit cannot hold
// when the plate flattens the ball: contact and limit conflict), and Stable Neo-Hookean
// (tets). Every step must be solved, finite; how flat it got, how much of its height came back
// and the worst violations are reported. The conflicting variant may instead stop on a
// cleanly refused step: its steps end far past the energy limit, which the engine now calls
// diverged (solver.divergence_violation_limit); it used to run on to nodes at 6.8 km/s and
// penetrations of 28 m. The surface is coarser than the lattice (0.125 m) to keep the contact
// rows few.
#include "engine/core/progress.hpp"
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

namespace crush {

struct Variant {
  const char* label;
  const char* body_keys;  // material and what goes with it
  bool full_only;         // the conflicting limit costs seconds a step
  bool may_stop;          // the constraints conflict: a clean stop is a pass too
};
inline const Variant kVariants[] = {
    {"corotational hex",
     R"("material": {"model": "corotational", "E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"stiffness": 0.01})",
     false, false},
    {"corotational hex, Umax 1 J",
     R"("material": {"model": "corotational", "E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"stiffness": 0.01},
        "energy_limit": {"Umax": 1.0})", true, true},
    {"stable_neo_hookean tet",
     R"("elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.3, "rho": 1000},
        "damping": {"mass": 2})", false, false}};

constexpr double kDiameter = 0.5;  // m
constexpr int kFreeSteps = 3;      // steps before the plate reaches the ball (0.02 m above it, at 0.47 m/s)
constexpr double kCrushedGap = 0.1 * kDiameter;

inline std::string scene_text(const Variant& v) {
  return format(R"({"bodies": [{"name": "ball", "shape": [{"type": "sphere", "radius": 0.25}], "cell_size": 0.1,
      "surface_resolution": 0.125, "transform": {"translate": [0, 0.251, 0]}, %s}],
    "obstacles": [{"type": "plane", "friction": 0.5},
      {"type": "plane", "normal": [0, -1, 0], "friction": 0.5,
       "motion": {"keyframes": [{"t": 0, "position": [0, 0.52, 0]}, {"t": 1.0, "position": [0, %g, 0]},
                                {"t": 1.5, "position": [0, %g, 0]}, {"t": 1.6, "position": [0, 1.5, 0]}]}}]})",
                v.body_keys, kCrushedGap, kCrushedGap);
}

}  // namespace crush

inline CaseResult run_crush_release(const Options& options) {
  using namespace crush;
  const int steps = options.quick ? 150 : 180;  // 2.5 s / 3 s at h = 1/60 s: 0.9 s / 1.4 s after release
  CaseResult r;
  r.details["runs"] = nlohmann::json::array();
  int completed = 0;
  double flattest = 1e300, least_recovered = 1e300, worst_penetration = 0;
  int runs = 0;
  for (const Variant& v : kVariants) {
    if (options.quick && v.full_only) continue;
    ++runs;
    const auto start = std::chrono::steady_clock::now();
    World world = world_from_text(scene_text(v), v.label);
    const double rest_height = surface_y_range(world, 0).second - surface_y_range(world, 0).first;
    double min_height = 1e300;
    Progress progress(std::string("crush_release, ") + v.label, steps);
    const RunOutcome run = run_steps(world, steps, [&](int k) {
      const auto [lo, hi] = surface_y_range(world, 0);
      min_height = std::min(min_height, hi - lo);
      progress.update(k + 1);
    });
    progress.finish();
    const auto [lo, hi] = surface_y_range(world, 0);
    const double crushed = min_height / rest_height, recovered = (hi - lo) / rest_height;
    // A stop counts only as the divergence test's (the refused step's last attempt past its
    // limit), once the plate presses.
    const bool stopped_cleanly = v.may_stop && run.finite && run.clean_rollback && run.refused_at >= kFreeSteps &&
                                 !(world.state().step_limit_violation <= world.model().solver.divergence_violation_limit);
    completed += run.completed() || stopped_cleanly;
    flattest = std::min(flattest, crushed);
    least_recovered = std::min(least_recovered, recovered);
    if (run.worst_violation.count("penetration"))
      worst_penetration = std::max(worst_penetration, run.worst_violation.at("penetration"));
    const double seconds = seconds_since(start);
    std::string violations;
    for (const auto& [kind, value] : run.worst_violation)
      if (has_constraint_kind(world.model(), kind)) violations += format(", worst %s %.3g", kind.c_str(), value);
    std::printf("  %-34s %s%s; crushed to %.0f %% of its height, back to %.0f %% at the end%s (%.1f s)\n", v.label,
                run.completed() || stopped_cleanly ? "" : "FAIL: ", describe(run).c_str(), 100 * crushed, 100 * recovered,
                violations.c_str(), seconds);
    std::fflush(stdout);
    nlohmann::json entry = to_json(run);
    entry["run"] = v.label;
    entry["crushed_height_ratio"] = crushed;
    entry["final_height_ratio"] = recovered;
    entry["seconds"] = seconds;
    r.details["runs"].push_back(entry);
  }
  r.pass = completed == runs;
  r.summary = format("%d/%d bodies crushed and released ran %d steps finite, no step refused (or, with conflicting "
                     "constraints, stopped cleanly); flattest %.0f %% of the rest height, least recovered %.0f %%, "
                     "worst penetration %.3g m",
                     completed, runs, steps, 100 * flattest, 100 * least_recovered, worst_penetration);
  return r;
}

}  // namespace sinew::stress
