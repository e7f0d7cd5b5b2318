// Contact through the whole step (engine/step/solve_constraints.cpp with
// engine/constraints/contact_rows.cpp): resting, sticking and sliding, impact, kinematic
// obstacles, friction bounds, skipping, determinism. Small lattices (0.1 m cells) so each
// case runs in seconds.
#include <doctest/doctest.h>

#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "engine/analysis/element_fields.hpp"
#include "engine/collision/obstacle_motion.hpp"
#include "engine/collision/mesh_sdf.hpp"
#include "engine/collision/obstacle_sdf.hpp"
#include "engine/constraints/contact_rows.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

const double kGravity = 9.81;

// A 0.34 m cube (64 cells of 0.1 m, 500 kg/m^3: 32 kg of lattice) on the plane y = 0,
// with extra obstacles and solver settings as JSON fragments. The cube is placed so that
// its lowest surface vertex is `gap` above the plane.
SceneDesc box_scene(double mu, const Vec3& gravity, double gap, const std::string& extra_obstacles = "",
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

World make_world(const SceneDesc& scene) {
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

Vec3 mean_node_position(const World& w) {
  Vec3 sum = Vec3::Zero();
  for (int n = 0; n < w.model().num_nodes; ++n) sum += w.state().x.segment<3>(3 * n);
  return sum / w.model().num_nodes;
}

Vec3 mean_node_velocity(const World& w) {
  Vec3 sum = Vec3::Zero();
  for (int n = 0; n < w.model().num_nodes; ++n) sum += w.state().v.segment<3>(3 * n);
  return sum / w.model().num_nodes;
}

// Smallest signed distance of any surface vertex to obstacle k at the current time.
double lowest_phi(const World& w, int k) {
  const ObstacleDesc& ob = w.model().obstacles[k];
  const Vec3 origin = obstacle_position(ob, w.state().t);
  double lowest = 1e300;
  for (const auto& surface : w.state().surface)
    for (const Vec3& p : surface) lowest = std::min(lowest, obstacle_sdf(ob, origin, p).phi);
  return lowest;
}

// Kinetic + gravitational (-m g . x) + elastic (1/2 u^T Ke u per element) energy, J.
double total_energy(const World& w) {
  const Model& m = w.model();
  double e = w.kinetic_energy();
  for (int n = 0; n < m.num_nodes; ++n) e -= m.node_mass[n] * m.gravity.dot(w.state().x.segment<3>(3 * n));
  for (int el = 0; el < m.num_elements; ++el) {
    const Vec24 u = element_corotated_displacement(m, w.state().x, el);
    e += 0.5 * hex8_limit_energy(m.references[m.element_reference[el]], u);
  }
  return e;
}

// Over the friction multipliers of the last step (kept by key in the warm start, since the
// row table is rebuilt after the last solve): the largest |lambda_f| - mu lambda_n (<= 0
// when all are within bounds) and how many sit on their bound with lambda_n > 0.
struct FrictionBounds {
  double excess = -1e300;
  int saturated = 0;
};
FrictionBounds friction_bounds(const World& w) {
  FrictionBounds out;
  const auto& warm = w.state().warm_start;  // sorted by key
  auto lambda_of = [&](uint64_t key) {
    const auto it = std::lower_bound(warm.begin(), warm.end(), std::make_pair(key, -1e300));
    REQUIRE((it != warm.end() && it->first == key));
    return it->second;
  };
  for (const auto& [key, lambda] : warm) {
    if ((key >> 60) != uint64_t(RowKind::Friction)) continue;
    const uint32_t vertex = static_cast<uint32_t>((key >> 24) & ((uint64_t(1) << 36) - 1));
    const uint32_t obstacle = static_cast<uint32_t>((key & 0xFFFFFF) / 2);
    const double bound = w.model().obstacles[obstacle].friction * lambda_of(contact_key(vertex, obstacle));
    out.excess = std::max(out.excess, std::abs(lambda) - bound);
    out.saturated += bound > 0 && std::abs(lambda) >= bound * (1 - 1e-9);
  }
  return out;
}

// Horizontal distance the cube slides in `seconds` on a plane tilted by theta (gravity
// tilted instead: g = 9.81 (sin theta, -cos theta, 0)).
double slide_on_incline(double theta, double mu, double seconds) {
  World w = make_world(box_scene(mu, kGravity * Vec3(std::sin(theta), -std::cos(theta), 0), 1e-4));
  const Vec3 start = mean_node_position(w);
  for (int i = 0; i < std::lround(seconds / w.model().h); ++i) REQUIRE(w.step());
  return mean_node_position(w).x() - start.x();
}

}  // namespace

TEST_CASE("contact: a box resting on a plane for 10 s penetrates at most 1 mm and does not drift") {
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4));
  const Vec3 start = mean_node_position(w);
  double deepest = 0, drift = 0;
  for (int i = 0; i < 600; ++i) {
    REQUIRE(w.step());
    deepest = std::max(deepest, -lowest_phi(w, 0));
    const Vec3 d = mean_node_position(w) - start;
    drift = std::max(drift, std::hypot(d.x(), d.z()));
  }
  MESSAGE("deepest penetration " << deepest << " m, largest horizontal drift " << drift << " m, "
                                 << w.state().rows.count(RowKind::Contact) << " contacts at the end");
  CHECK(deepest <= 1e-3);
  CHECK(deepest <= w.model().solver.contact_tolerance);  // what SQP promises
  CHECK(drift < 1e-3);
  CHECK(w.kinetic_energy() < 1e-6);  // at rest
}

TEST_CASE("contact: on an incline the box sticks below atan(mu), slides above; threshold within 3 %") {
  const double mu = 0.5, critical = std::atan(mu), seconds = 1.0;
  // Sliding at 3 % above the critical angle accelerates at g (sin - mu cos) ~ 0.15 m/s^2,
  // 7 cm in 1 s; sticking moves the centre only by the elastic shear (< 1 mm here).
  const double slides = 0.01;
  double lo = 0.5 * critical, hi = 1.5 * critical;
  REQUIRE(slide_on_incline(lo, mu, seconds) < slides);
  REQUIRE(slide_on_incline(hi, mu, seconds) > slides);
  while (hi - lo > 0.005 * critical) {
    const double mid = 0.5 * (lo + hi);
    (slide_on_incline(mid, mu, seconds) > slides ? hi : lo) = mid;
  }
  const double threshold = 0.5 * (lo + hi);
  MESSAGE("sliding threshold " << threshold * 180 / std::numbers::pi << " deg, atan(mu) "
                               << critical * 180 / std::numbers::pi << " deg, error "
                               << 100 * (threshold / critical - 1) << " %");
  CHECK(std::abs(threshold / critical - 1) < 0.03);
}

TEST_CASE("contact: friction multipliers never leave [-mu lambda_n, mu lambda_n]") {
  // Sliding down a 35 degree incline (above atan 0.5 = 26.6 degrees): friction saturates.
  const double theta = 35 * std::numbers::pi / 180;
  World w = make_world(box_scene(0.5, kGravity * Vec3(std::sin(theta), -std::cos(theta), 0), 0.02));
  double worst = -1e300;
  int saturated = 0;
  for (int i = 0; i < 60; ++i) {
    REQUIRE(w.step());
    const FrictionBounds b = friction_bounds(w);
    worst = std::max(worst, b.excess);
    saturated += b.saturated;
  }
  MESSAGE("largest |lambda_f| - mu lambda_n: " << worst << " N s; " << saturated << " saturated friction rows");
  CHECK(saturated > 0);  // the bound was reached, so the check below is not vacuous
  CHECK(worst <= 1e-12);
}

TEST_CASE("contact: a sphere dropped on a plane does not penetrate and its energy never grows") {
  const std::string text = R"({"h": 0.0166666666667,
    "bodies": [{"shape": [{"type": "sphere", "radius": 0.25}], "transform": {"translate": [0.01, 0.6, 0.02]},
      "cell_size": 0.1, "surface_resolution": 0.06, "material": {"E": 1e5, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})";
  const SceneDesc scene = parse_scene_text(text, "sphere", ".");
  World w = make_world(scene);
  const double tolerance = w.model().solver.contact_tolerance;
  double mass = w.model().node_mass.sum();
  // Energy may rise only by what the penetration correction adds: lifting the body by at
  // most the tolerance, m g tol per step.
  const double allowed = mass * kGravity * tolerance;
  double previous = total_energy(w), largest_rise = -1e300, deepest = 0;
  const double initial = previous;
  int contact_steps = 0;
  for (int i = 0; i < 180; ++i) {
    REQUIRE(w.step());
    const double e = total_energy(w);
    largest_rise = std::max(largest_rise, e - previous);
    previous = e;
    deepest = std::max(deepest, -lowest_phi(w, 0));
    contact_steps += w.state().rows.count(RowKind::Contact) > 0;
  }
  MESSAGE("mass " << mass << " kg; energy " << initial << " J -> " << previous << " J; largest rise in a step "
                  << largest_rise << " J (allowed " << allowed << "); deepest penetration " << deepest
                  << " m; " << contact_steps << " steps with contacts");
  CHECK(contact_steps > 60);
  CHECK(deepest <= tolerance);
  CHECK(largest_rise <= allowed);
  CHECK(previous < initial);
}

TEST_CASE("contact: a kinematic plate pushes a body along the ground and never tunnels") {
  // A plate (box obstacle) 2 cm left of the cube moving right at 0.5 m/s for 1.5 s.
  const std::string plate = R"(, {"type": "box", "half_extents": [0.02, 0.3, 0.3], "friction": 0.2,
      "motion": {"velocity": [0.5, 0, 0]}, "center": [-0.21, 0.2, 0]})";
  World w = make_world(box_scene(0.3, Vec3(0, -kGravity, 0), 1e-4, plate));
  const double tolerance = w.model().solver.contact_tolerance;
  const Vec3 start = mean_node_position(w);
  double deepest_plate = 0, deepest_ground = 0;
  for (int i = 0; i < 90; ++i) {
    REQUIRE(w.step());
    deepest_plate = std::max(deepest_plate, -lowest_phi(w, 1));
    deepest_ground = std::max(deepest_ground, -lowest_phi(w, 0));
  }
  const double pushed = mean_node_position(w).x() - start.x();
  MESSAGE("plate moved 0.75 m, body " << pushed << " m; deepest penetration: plate " << deepest_plate
                                      << " m, ground " << deepest_ground << " m");
  // The plate reaches the cube after ~0.04 s (2 cm gap at 0.5 m/s, minus the cube's own
  // 1 cm left overhang of the lattice mean): the body must follow for the rest, about 0.7 m.
  CHECK(pushed > 0.65);
  CHECK(pushed < 0.75);
  CHECK(deepest_plate <= tolerance);
  CHECK(deepest_ground <= tolerance);
}

TEST_CASE("contact: a plate moving by keyframes squeezes a body onto the ground without tunnelling") {
  // The plate comes down 6 cm onto the cube's top face (cube top at 0.34 m), holds, and lifts.
  const std::string plate = R"(, {"type": "box", "half_extents": [0.4, 0.05, 0.4], "friction": 0.5,
      "motion": {"keyframes": [{"t": 0, "position": [0, 0.40, 0]}, {"t": 0.5, "position": [0, 0.34, 0]},
                               {"t": 1.0, "position": [0, 0.34, 0]}, {"t": 1.5, "position": [0, 0.6, 0]}]}})";
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4, plate, 2e5));
  const double tolerance = w.model().solver.contact_tolerance;
  double deepest_plate = 0, deepest_ground = 0, squeezed = 0;
  for (int i = 0; i < 120; ++i) {
    REQUIRE(w.step());
    deepest_plate = std::max(deepest_plate, -lowest_phi(w, 1));
    deepest_ground = std::max(deepest_ground, -lowest_phi(w, 0));
    double top = -1e300;
    for (const Vec3& p : w.state().surface[0]) top = std::max(top, p.y());
    squeezed = std::max(squeezed, 0.34 + 1e-4 - top);
  }
  MESSAGE("largest squeeze of the cube's height " << squeezed << " m; deepest penetration: plate "
                                                  << deepest_plate << " m, ground " << deepest_ground << " m");
  CHECK(squeezed > 0.04);  // the plate bottom reaches 0.29 m: the 0.34 m cube is squeezed ~5 cm
  CHECK(deepest_plate <= tolerance);
  CHECK(deepest_ground <= tolerance);
}

TEST_CASE("contact: a moving table carries a box along by friction") {
  // The plane slides along x at 1 m/s (its distance field does not change, only its velocity).
  // Kinetic friction accelerates the box at mu g = 4.9 m/s^2 until it moves with the table.
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4);
  scene.obstacles[0].motion.velocity = Vec3(1, 0, 0);
  World w = make_world(scene);
  for (int i = 0; i < 6; ++i) REQUIRE(w.step());
  const double early = mean_node_velocity(w).x();  // after 0.1 s: mu g t = 0.49 m/s
  for (int i = 0; i < 54; ++i) REQUIRE(w.step());
  const double late = mean_node_velocity(w).x();
  MESSAGE("box velocity after 0.1 s " << early << " m/s (mu g t = " << 0.5 * kGravity * 0.1 << "), after 1 s "
                                      << late << " m/s");
  CHECK(early == doctest::Approx(0.5 * kGravity * 0.1).epsilon(0.05));
  CHECK(late == doctest::Approx(1.0).epsilon(0.01));
}

TEST_CASE("contact: a box rests on a triangle-mesh slab as it does on a plane") {
  // A 2 x 0.2 x 2 m slab, top face at y = 0, as 12 outward triangles; the plane is moved away.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("sinew_slab_" + std::to_string(::getpid()) + ".obj")).string();
  std::ofstream(path) << "v -1 -0.2 -1\nv 1 -0.2 -1\nv 1 -0.2 1\nv -1 -0.2 1\n"
                         "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
                         "f 1 2 3\nf 1 3 4\nf 5 7 6\nf 5 8 7\nf 1 5 6\nf 1 6 2\n"
                         "f 2 6 7\nf 2 7 3\nf 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n";
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4,
                              R"(, {"type": "mesh", "mesh": ")" + path + R"(", "friction": 0.5})");
  scene.obstacles[0].point = Vec3(0, -10, 0);
  World w = make_world(scene);
  std::filesystem::remove(path);
  const Vec3 start = mean_node_position(w);
  double deepest = 0;
  for (int i = 0; i < 60; ++i) {
    REQUIRE(w.step());
    deepest = std::max(deepest, -lowest_phi(w, 1));
  }
  const Vec3 moved = mean_node_position(w) - start;
  MESSAGE("deepest penetration into the slab " << deepest << " m; the box moved " << moved.transpose() << " m");
  CHECK(deepest <= w.model().solver.contact_tolerance);
  CHECK(w.state().rows.count(RowKind::Contact) > 20);
  CHECK(std::hypot(moved.x(), moved.z()) < 1e-4);
  CHECK(moved.y() > -1e-3);  // elastic settling only
}

// Deepest penetration of any surface vertex of one body into another's deformed surface,
// measured independently of the rows: a fresh signed-distance mesh of each surface.
double deepest_between_bodies(const World& w) {
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

TEST_CASE("contact: a scene without obstacles or limits skips the constraint stage and says why") {
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 0.1);
  scene.obstacles.clear();
  World w = make_world(scene);
  REQUIRE(w.step());
  CHECK(w.profile().skipped[static_cast<int>(Stage::Rows)] == "scene has one body, no obstacles and no energy limits");
  CHECK(w.profile().violation.count("penetration") == 0);
  CHECK(w.state().rows.size() == 0);
}

TEST_CASE("contact: the same state hash for 1 and 2 threads") {
  auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const double theta = 35 * std::numbers::pi / 180;
    World w = make_world(box_scene(0.5, kGravity * Vec3(std::sin(theta), -std::cos(theta), 0), 0.02));
    for (int i = 0; i < 30; ++i) w.step();
    return w.state_hash();
  };
  CHECK(run(1) == run(2));
}
