#pragma once
// Case incompressible: nu = 0.499 (lambda / mu = 499) on linear corotational bodies (hex
// lattice and its tet split) and a Stable Neo-Hookean body: a cantilever sagging under
// gravity and a block thrown onto the ground at 3 m/s. Every step must be solved, finite;
// the range of det F over elements and steps is reported (near 1 when the volume holds).
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

namespace incompressible {

struct Body {
  const char* label;
  const char* model;
  const char* elements;
};
inline const Body kBodies[] = {{"corotational hex", "corotational", "hex"},
                               {"corotational tet", "corotational", "tet"},
                               {"stable_neo_hookean tet", "stable_neo_hookean", "tet"}};

// A 1 m x 0.2 m x 0.2 m cantilever clamped at x = -0.5, or a 0.4 m block dropped onto a plane.
inline std::string scene_text(const Body& body, bool cantilever) {
  const std::string material =
      format(R"("elements": "%s", "material": {"model": "%s", "E": 1e5, "nu": 0.499, "rho": 1000},
             "damping": {"mass": 1})",
             body.elements, body.model);
  if (cantilever)
    return R"({"bodies": [{"name": "beam", "shape": [{"type": "box", "half_extents": [0.5, 0.1, 0.1]}],
      "cell_size": 0.1, "fixed": [{"box": {"min": [-0.6, -0.2, -0.2], "max": [-0.45, 0.2, 0.2]}}], )" +
           material + "}]}";
  return R"({"bodies": [{"name": "block", "shape": [{"type": "box", "half_extents": [0.2, 0.2, 0.2]}],
      "cell_size": 0.1, "transform": {"translate": [0, 0.5, 0]}, "velocity": [0, -3, 0], )" +
         material + R"(}], "obstacles": [{"type": "plane", "friction": 0.5}]})";
}

}  // namespace incompressible

inline CaseResult run_incompressible(const Options& options) {
  using namespace incompressible;
  const int steps = options.quick ? 60 : 180;  // 1 s / 3 s at h = 1/60 s
  CaseResult r;
  r.details["nu"] = 0.499;
  r.details["runs"] = nlohmann::json::array();
  int runs = 0, completed = 0;
  double J_lo = 1e300, J_hi = -1e300;
  for (const Body& body : kBodies) {
    for (const bool cantilever : {true, false}) {
      const auto start = std::chrono::steady_clock::now();
      const std::string what = std::string(body.label) + (cantilever ? " cantilever" : " block drop");
      World world = world_from_text(scene_text(body, cantilever), what);
      double lo = 1e300, hi = -1e300;
      const RunOutcome run = run_steps(world, steps, [&](int) {
        const auto [a, b] = volume_ratio_range(world);
        lo = std::min(lo, a), hi = std::max(hi, b);
      });
      ++runs;
      completed += run.completed();
      J_lo = std::min(J_lo, lo), J_hi = std::max(J_hi, hi);
      const double seconds = seconds_since(start);
      std::printf("  %-34s %s%s, det F in [%.4f, %.4f] (%.1f s)\n", what.c_str(), run.completed() ? "" : "FAIL: ",
                  describe(run).c_str(), lo, hi, seconds);
      std::fflush(stdout);
      nlohmann::json entry = to_json(run);
      entry["run"] = what;
      entry["det_F_min"] = lo;
      entry["det_F_max"] = hi;
      entry["seconds"] = seconds;
      r.details["runs"].push_back(entry);
    }
  }
  r.pass = completed == runs;
  r.summary = format("%d/%d runs at nu 0.499 ran %d steps finite, no step refused; det F over all elements and "
                     "steps in [%.4f, %.4f]",
                     completed, runs, steps, J_lo, J_hi);
  return r;
}

}  // namespace sinew::stress
