// Body-vs-body contact through the whole step (engine/constraints/body_contact_rows.cpp):
// stacking and a head-on collision.
#include <doctest/doctest.h>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

TEST_CASE("contact: two boxes stacked on a plane stay stacked without interpenetrating") {
  char text[2048];
  std::snprintf(text, sizeof text, R"({"h": %.17g,
    "bodies": [{"name": "bottom", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
                "transform": {"translate": [0.013, 0.1704, 0.007]}, "cell_size": 0.1, "surface_resolution": 0.085,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}},
               {"name": "top", "shape": [{"type": "box", "half_extents": [0.12, 0.12, 0.12]}],
                "transform": {"translate": [0.03, 0.47, 0.01]}, "cell_size": 0.08, "surface_resolution": 0.08,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})", 1.0 / 60);
  World w = make_world(parse_scene_text(text, "stack", "."));
  const double tolerance = w.model().solver.contact_tolerance;
  double deepest = 0;
  for (int i = 0; i < 60; ++i) {
    REQUIRE(w.step());
    if (i % 10 == 9) deepest = std::max(deepest, deepest_between_bodies(w));
  }
  double lowest_top = 1e300;
  for (const Vec3& p : w.state().surface[1]) lowest_top = std::min(lowest_top, p.y());
  MESSAGE("deepest vertex of one box inside the other " << deepest << " m; top box's lowest vertex at "
                                                         << lowest_top << " m; kinetic energy " << w.kinetic_energy() << " J");
  CHECK(deepest <= tolerance);
  CHECK(lowest_top > 0.3);  // still on the 0.34 m bottom box (dropped 2 cm onto it)
  CHECK(w.kinetic_energy() < 1e-3);
}

TEST_CASE("contact: two spheres colliding in free space: no interpenetration, momentum conserved") {
  const std::string text = R"({"h": 0.0166666666667, "gravity": [0, 0, 0],
    "bodies": [{"name": "left", "shape": [{"type": "sphere", "radius": 0.2}], "cell_size": 0.1,
                "transform": {"translate": [-0.3, 0, 0]}, "velocity": [1, 0, 0],
                "surface_resolution": 0.06, "material": {"E": 2e5, "nu": 0.3, "rho": 500}},
               {"name": "right", "shape": [{"type": "sphere", "radius": 0.2}], "cell_size": 0.1,
                "transform": {"translate": [0.3, 0.05, 0]}, "velocity": [-1, 0, 0],
                "surface_resolution": 0.06, "material": {"E": 2e5, "nu": 0.3, "rho": 500}}]})";
  const SceneDesc scene = parse_scene_text(text, "spheres", ".");
  World w = make_world(scene);
  const Model& m = w.model();
  auto momentum = [&] {
    Vec3 p = Vec3::Zero();
    for (int n = 0; n < m.num_nodes; ++n) p += m.node_mass[n] * w.state().v.segment<3>(3 * n);
    return p;
  };
  const Vec3 before = momentum();
  const double scale = m.node_mass.sum() * 1.0;  // |m v| of either sphere, roughly
  double deepest = 0;
  int contact_steps = 0;
  for (int i = 0; i < 45; ++i) {
    REQUIRE(w.step());
    deepest = std::max(deepest, deepest_between_bodies(w));
    contact_steps += w.state().rows.count(RowKind::Contact) > 0;
  }
  const Vec3 after = momentum();
  double gap = 1e300;  // closing speed sign: the left sphere's centre must not pass the right's
  Vec3 left = Vec3::Zero(), right = Vec3::Zero();
  for (const Vec3& p : w.state().surface[0]) left += p / w.state().surface[0].size();
  for (const Vec3& p : w.state().surface[1]) right += p / w.state().surface[1].size();
  gap = right.x() - left.x();
  MESSAGE(contact_steps << " steps in contact; deepest interpenetration " << deepest << " m; momentum "
                        << before.transpose() << " -> " << after.transpose() << "; centres " << gap << " m apart");
  CHECK(contact_steps > 0);
  CHECK(deepest <= m.solver.contact_tolerance);
  CHECK((after - before).norm() < 1e-9 * scale);
  CHECK(gap > 0.3);  // they did not pass through each other
}
