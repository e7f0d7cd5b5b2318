#pragma once
// Shared by the paper 001 scene tests: load a shipped scene, measure stretches of tets.
#include <doctest/doctest.h>

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

}  // namespace sinew::paper001
