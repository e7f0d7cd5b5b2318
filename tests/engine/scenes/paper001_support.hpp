#pragma once
// Shared by the paper 001 scene tests: load a shipped scene, measure stretches of tets, run
// the flat-pressed finger and count its SQP's work.
#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <string>

#include "engine/assembly/element_kernels.hpp"
#include "engine/constraints/strain_limit_rows.hpp"
#include "engine/simulate_frame.hpp"

namespace sinew::paper001 {

inline World load_world(const std::string& name) {
  const SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

// Largest and smallest stretch |F d| of a rest direction d over all elements.
struct StretchRange {
  double lo = 1e300, hi = -1e300;
};
inline StretchRange stretch_along(const World& world, const Vec3& d) {
  StretchRange r;
  const Model& m = world.model();
  for (int e = 0; e < m.num_elements; ++e) {
    const double s = (element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e)) * d).norm();
    r.lo = std::min(r.lo, s);
    r.hi = std::max(r.hi, s);
  }
  return r;
}

// Extent of the nodes along d.
inline double extent_along(const Model& m, const VecX& x, const Vec3& d) {
  double lo = 1e300, hi = -1e300;
  for (int n = 0; n < m.num_nodes; ++n) {
    lo = std::min(lo, x.segment<3>(3 * n).dot(d));
    hi = std::max(hi, x.segment<3>(3 * n).dot(d));
  }
  return hi - lo;
}

// A shipped scene, sleep off (as benchmarked and measured: a finger asleep would test
// nothing), `configure`d, run for `frames` steps: its SQP's work and worst strain violation.
struct SqpRun {
  double worst_violation = 0;  // over the steps, of the strain limits
  double tolerance = 0;
  int sqp_iterations = 0;
  int backtracks = 0;
  int stalls_accepted = 0;
  int restorations_accepted = 0;
  int capped_steps = 0;  // steps whose SQP ended at its iteration cap (as extended, if it was)
};
inline SqpRun run_counting_sqp(const std::string& name, const std::function<void(SceneDesc&)>& configure,
                               int frames) {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
  scene.solver.sleep_steps = 0;
  configure(scene);
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  SqpRun r;
  r.tolerance = world.model().solver.strain_tolerance;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    r.worst_violation = std::max(r.worst_violation, worst_strain_limit_violation(world.model(), world.state().x));
    r.sqp_iterations += world.profile().iteration("sqp");
    r.backtracks += world.profile().iteration("sqp_backtracks");
    r.stalls_accepted += world.profile().iteration("sqp_stalls_accepted");
    r.restorations_accepted += world.profile().iteration("sqp_restorations_accepted");
    if (world.profile().ended_at_sqp_cap(world.model().solver.sqp_max_iterations)) ++r.capped_steps;
  }
  MESSAGE(name << ": SQP iterations " << r.sqp_iterations << ", backtracks " << r.backtracks << ", stalls accepted "
               << r.stalls_accepted << ", restorations accepted " << r.restorations_accepted
               << ", worst strain violation " << r.worst_violation << ", steps at the cap " << r.capped_steps);
  return r;
}

// The finger of fig. 3 pressed flat.
using FlatFingerRun = SqpRun;
inline FlatFingerRun run_flat_finger(const std::function<void(SceneDesc&)>& configure, int frames) {
  return run_counting_sqp("paper001_finger_flat_anisotropic", configure, frames);
}

}  // namespace sinew::paper001
