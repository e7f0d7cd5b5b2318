#pragma once
// Shared by the contact step tests: a small cube on the plane y = 0 and measurements of a
// running World (positions, velocities, distances, energy).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/analysis/element_fields.hpp"
#include "engine/collision/mesh_sdf.hpp"
#include "engine/collision/obstacle_motion.hpp"
#include "engine/collision/obstacle_sdf.hpp"
#include "engine/world.hpp"

namespace sinew::test {

constexpr double kGravity = 9.81;

// A 0.34 m cube (64 cells of 0.1 m, 500 kg/m^3: 32 kg of lattice) on the plane y = 0,
// with extra obstacles and solver settings as JSON fragments. The cube is placed so that
// its lowest surface vertex is `gap` above the plane.
inline SceneDesc box_scene(double mu, const Vec3& gravity, double gap, const std::string& extra_obstacles = "",
                             double E = 1e6, const std::string& solver = "{}") {
  char text[2048];
  std::snprintf(text, sizeof text, R"({"h": %.17g, "gravity": [%.17g, %.17g, %.17g], "solver": %s,
    "bodies": [{"name": "box", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
      "transform": {"translate": [0.013, 0.5, 0.007]}, "cell_size": 0.1, "surface_resolution": 0.06,
      "material": {"E": %.17g, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": %.17g}%s]})",
                1.0 / 60, gravity.x(), gravity.y(), gravity.z(), solver.c_str(), E, mu, extra_obstacles.c_str());
  SceneDesc scene = parse_scene_text(text, "contact", ".");
  const Model probe = build_model(scene, [](const std::string&) {});
  double lowest = 1e300;
  for (const Vec3& p : probe.bodies[0].rest_surface.vertices) lowest = std::min(lowest, p.y());
  scene.bodies[0].translate.y() += gap - lowest;
  return scene;
}

inline World make_world(const SceneDesc& scene) {
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

inline Vec3 mean_node_position(const World& w) {
  Vec3 sum = Vec3::Zero();
  for (int n = 0; n < w.model().num_nodes; ++n) sum += w.state().x.segment<3>(3 * n);
  return sum / w.model().num_nodes;
}

inline Vec3 mean_node_velocity(const World& w) {
  Vec3 sum = Vec3::Zero();
  for (int n = 0; n < w.model().num_nodes; ++n) sum += w.state().v.segment<3>(3 * n);
  return sum / w.model().num_nodes;
}

// Smallest signed distance of any surface vertex to obstacle k at the current time.
inline double lowest_phi(const World& w, int k) {
  const ObstacleDesc& ob = w.model().obstacles[k];
  const Vec3 origin = obstacle_position(ob, w.state().t);
  double lowest = 1e300;
  for (const auto& surface : w.state().surface)
    for (const Vec3& p : surface) lowest = std::min(lowest, obstacle_sdf(ob, origin, p).phi);
  return lowest;
}

// Kinetic + gravitational (-m g . x) + elastic (1/2 u^T Ke u per element) energy, J.
inline double total_energy(const World& w) {
  const Model& m = w.model();
  double e = w.kinetic_energy();
  for (int n = 0; n < m.num_nodes; ++n) e -= m.node_mass[n] * m.gravity.dot(w.state().x.segment<3>(3 * n));
  for (int el = 0; el < m.num_elements; ++el) {
    const Vec24 u = element_corotated_displacement(m, w.state().x, el);
    e += 0.5 * hex8_limit_energy(m.references[m.element_reference[el]], u);
  }
  return e;
}

// Deepest penetration of any surface vertex of one body into another's deformed surface,
// measured independently of the rows: a fresh signed-distance mesh of each surface.
inline double deepest_between_bodies(const World& w) {
  const Model& m = w.model();
  double deepest = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const MeshSdf surface(TriMesh{w.state().surface[b], m.bodies[b].rest_surface.triangles});
    for (size_t a = 0; a < m.bodies.size(); ++a)
      if (a != b)
        for (const Vec3& p : w.state().surface[a]) deepest = std::max(deepest, -surface.sdf(p).phi);
  }
  return deepest;
}

}  // namespace sinew::test
