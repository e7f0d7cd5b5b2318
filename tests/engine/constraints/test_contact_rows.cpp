// Contact rows (engine/constraints/contact_rows.cpp): Jacobians against finite differences
// of the row values for every obstacle type, friction values, the broad phase against a
// brute-force search, kept rows, stable keys and thread-count independence.
#include <doctest/doctest.h>

#include <tbb/global_control.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "engine/collision/obstacle_motion.hpp"
#include "engine/collision/obstacle_sdf.hpp"
#include "engine/constraints/contact_rows.hpp"
#include "engine/geometry/surface_mesher.hpp"
#include "engine/io/mesh_export.hpp"

using namespace sinew;

namespace {

const char* const kAnalytic[] = {
    R"({"type": "plane", "point": [0, -0.12, 0], "normal": [0.2, 1, 0.1], "friction": 0.4})",
    R"({"type": "box", "center": [0.3, 0.05, 0], "half_extents": [0.15, 0.1, 0.3], "rotation_deg": [10, 20, 30], "friction": 0.4})",
    R"({"type": "sphere", "center": [0, 0.4, 0.1], "radius": 0.25, "friction": 0.4})",
    R"({"type": "capsule", "center": [-0.1, 0, 0.35], "radius": 0.1, "length": 0.4, "rotation_deg": [0, 0, 70], "friction": 0.4})"};

std::string mesh_obstacle();

// Every obstacle type, one JSON object each.
std::vector<std::string> obstacles() {
  std::vector<std::string> all(std::begin(kAnalytic), std::end(kAnalytic));
  all.push_back(mesh_obstacle());
  return all;
}

// A closed mesh obstacle: an ellipsoid surface written to a temporary OBJ (removed at exit).
std::string mesh_obstacle() {
  struct TempObj {
    std::string path;
    TempObj() {
      Shape shape;
      Primitive p;
      p.kind = PrimitiveKind::Ellipsoid;
      p.size = Vec3(0.3, 0.15, 0.25);
      shape.parts.push_back(p);
      path = (std::filesystem::temp_directory_path() / ("sinew_contact_mesh_" + std::to_string(::getpid()) + ".obj"))
                 .string();
      write_obj(path, mesh_shape_surface(shape, 0.05));
    }
    ~TempObj() { std::filesystem::remove(path); }
  };
  static const TempObj obj;
  return R"({"type": "mesh", "mesh": ")" + obj.path +
         R"(", "center": [0.2, -0.25, 0.05], "rotation_deg": [0, 30, 0], "friction": 0.4})";
}

// A 0.25 m sphere on 0.1 m cells, with one obstacle cutting into it.
Model model_with(const std::string& obstacle, const std::string& solver = R"({"contact_margin": 0.03})") {
  const std::string text = R"({"h": 0.01, "solver": )" + solver + R"(,
    "bodies": [{"shape": [{"type": "sphere", "radius": 0.25}], "cell_size": 0.1,
                "surface_resolution": 0.05, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}],
    "obstacles": [)" + obstacle + "]}";
  return build_model(parse_scene_text(text, "contact", "."), [](const std::string&) {});
}

// Rest positions moved by a smooth, non-rigid field (a few cm), and some velocity field.
VecX deformed(const Model& m, double amount) {
  VecX x = m.rest_x;
  const Mat3 Q = Eigen::AngleAxisd(0.3, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
  for (int n = 0; n < m.num_nodes; ++n) {
    const Vec3 X = m.rest_x.segment<3>(3 * n);
    x.segment<3>(3 * n) = Q * X + amount * Vec3(std::sin(7 * X.y()), std::cos(5 * X.z()), std::sin(6 * X.x() + 1));
  }
  return x;
}

VecX velocities(const Model& m) {
  VecX v(3 * m.num_nodes);
  for (int i = 0; i < v.size(); ++i) v[i] = std::sin(0.37 * i + 0.2);
  return v;
}

uint32_t vertex_of(uint64_t key) { return static_cast<uint32_t>((key >> 24) & ((uint64_t(1) << 36) - 1)); }

int find_row(const RowTable& rows, uint64_t key) {
  for (int i = 0; i < rows.size(); ++i)
    if (rows.key[i] == key) return i;
  return -1;
}

// Value of the row `key` (kept, so that it exists) at (x, v).
double row_value(const Model& m, double t, const VecX& x, const VecX& v, uint64_t key) {
  RowTable rows;
  const std::vector<uint64_t> keep{contact_key(vertex_of(key), 0)};
  add_contact_rows(m, t, x, v, keep, rows);
  const int i = find_row(rows, key);
  REQUIRE(i >= 0);
  return rows.value[i];
}

}  // namespace

TEST_CASE("contact rows: tangents are an orthonormal right-handed frame, continuous in the normal") {
  Vec3 t1, t2;
  contact_tangents(Vec3::UnitY(), t1, t2);
  CHECK((t1 - Vec3::UnitZ()).norm() == 0);
  CHECK((t2 - Vec3::UnitX()).norm() == 0);
  // A slightly tilted normal (a deformed surface) turns the frame slightly, whichever way
  // it tilts: no jump between axes that would scramble warm-started friction.
  for (const Vec3& tilt : {Vec3(1e-4, 0, 3e-5), Vec3(3e-5, 0, 1e-4), Vec3(-2e-4, 0, -1e-4)}) {
    Vec3 s1, s2;
    contact_tangents((Vec3::UnitY() + tilt).normalized(), s1, s2);
    CHECK((s1 - t1).norm() < 1e-3);
    CHECK((s2 - t2).norm() < 1e-3);
  }
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int i = 0; i < 200; ++i) {
    const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
    contact_tangents(n, t1, t2);
    REQUIRE(std::abs(t1.norm() - 1) < 1e-12);
    REQUIRE(std::abs(t1.dot(n)) < 1e-12);
    REQUIRE((t1.cross(t2) - n).norm() < 1e-12);
  }
}

TEST_CASE("contact rows: normal Jacobians are d phi(p(x)) / dx, friction Jacobians d value / (h dv)") {
  for (const std::string& obstacle : obstacles()) {
    const Model m = model_with(obstacle);
    const VecX x = deformed(m, 0.02), v = velocities(m);
    const double t = 0.5;
    RowTable rows;
    add_contact_rows(m, t, x, v, {}, rows);
    REQUIRE(rows.count(RowKind::Contact) >= 5);
    REQUIRE(rows.count(RowKind::Friction) == 2 * rows.count(RowKind::Contact));
    double worst = 0;
    int checked = 0;
    const int stride = std::max(1, rows.size() / 40);  // about 40 rows, normal and friction
    for (int i = 0; i < rows.size(); i += stride) {
      const bool normal = rows.kind[i] == RowKind::Contact;
      for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e) {
        for (int a = 0; a < 3; ++a) {
          // Normal rows: central difference of C = phi over the node position. phi is
          // smooth away from the obstacles' kinks, the step is 1e-6 m: error ~1e-9.
          // Friction rows: the value h t . (v_p - v_obstacle) is linear in v.
          const double step = 1e-6;
          VecX xp = x, xm = x, vp = v, vm = v;
          (normal ? xp : vp)[3 * rows.nodes[e] + a] += step;
          (normal ? xm : vm)[3 * rows.nodes[e] + a] -= step;
          const double d = (row_value(m, t, xp, vp, rows.key[i]) - row_value(m, t, xm, vm, rows.key[i])) / (2 * step);
          const double expected = normal ? rows.jac[e][a] : m.h * rows.jac[e][a];
          worst = std::max(worst, std::abs(d - expected));
          ++checked;
        }
      }
    }
    MESSAGE(obstacle << ": " << rows.count(RowKind::Contact) << " contacts, " << checked
                     << " derivatives, worst error " << worst);
    CHECK(worst < 1e-7);
  }
}

TEST_CASE("contact rows: values, bounds and coupling of one contact") {
  // A kinematic plane moving along x: friction must see its velocity.
  const Model m = model_with(R"({"type": "plane", "point": [0, -0.2, 0], "motion": {"velocity": [0.7, 0.1, 0]}, "friction": 0.3})");
  const VecX x = deformed(m, 0.01), v = velocities(m);
  const double t_end = 0.3;
  RowTable rows;
  add_contact_rows(m, t_end, x, v, {}, rows);
  REQUIRE(rows.size() > 0);
  const ObstacleDesc& ob = m.obstacles[0];
  const Vec3 origin = obstacle_position(ob, t_end), v_ob = obstacle_velocity(ob, t_end - m.h, t_end);
  CHECK((v_ob - Vec3(0.7, 0.1, 0)).norm() < 1e-9);
  const Body& body = m.bodies[0];
  for (int i = 0; i < rows.size(); i += 3) {
    REQUIRE(rows.kind[i] == RowKind::Contact);
    const int vertex = static_cast<int>(vertex_of(rows.key[i]));
    const auto& cell = body.lattice.cells[body.embedding.cell[vertex]];
    Vec3 p = Vec3::Zero(), vp = Vec3::Zero();
    for (int n = 0; n < 8; ++n) {
      p += body.embedding.weights[vertex][n] * x.segment<3>(3 * cell[n]);
      vp += body.embedding.weights[vertex][n] * v.segment<3>(3 * cell[n]);
    }
    const SdfSample s = plane_sdf(origin, ob.normal, p);
    CHECK(rows.value[i] == doctest::Approx(s.phi).epsilon(1e-12));
    CHECK(s.phi < contact_margin(m, 0));
    CHECK(rows.lo[i] == 0);
    CHECK(rows.hi[i] > 1e100);
    CHECK(rows.key[i] == contact_key(vertex, 0));
    Vec3 t[2];
    contact_tangents(ob.normal, t[0], t[1]);
    for (int j = 0; j < 2; ++j) {
      const int f = i + 1 + j;
      CHECK(rows.kind[f] == RowKind::Friction);
      CHECK(rows.normal_row[f] == i);
      CHECK(rows.mu[f] == 0.3);
      CHECK(rows.key[f] == friction_key(vertex, 0, j));
      CHECK(rows.value[f] == doctest::Approx(m.h * t[j].dot(vp - v_ob)).epsilon(1e-12));
    }
  }
}

TEST_CASE("contact rows: the broad phase finds exactly the sites a brute-force search finds") {
  for (const std::string& obstacle : obstacles()) {
    const Model m = model_with(obstacle);
    const Body& body = m.bodies[0];
    for (double amount : {0.0, 0.03}) {
      const VecX x = deformed(m, amount);
      RowTable rows;
      const ContactRowsResult r = add_contact_rows(m, 0, x, velocities(m), {}, rows);
      std::vector<uint64_t> found, expected;
      for (int i = 0; i < rows.size(); ++i)
        if (rows.kind[i] == RowKind::Contact) found.push_back(rows.key[i]);
      std::vector<Vec3> surface;
      compute_embedded_positions(body.embedding, body.lattice, x, 0, surface);
      // One row per site (cell, eighth of the cell by rest position): its deepest vertex,
      // when that is within the margin.
      double deepest = 0;
      std::map<std::pair<int, int>, std::pair<double, int>> site_best;
      for (size_t i = 0; i < surface.size(); ++i) {
        const double phi = obstacle_sdf(m.obstacles[0], m.obstacles[0].point, surface[i]).phi;
        deepest = std::max(deepest, -phi);
        const int cell = body.embedding.cell[i];
        const auto& g = body.lattice.cell_coords[cell];
        const Vec3 centre = body.lattice.origin + body.lattice.cell_size * Vec3(g[0] + 0.5, g[1] + 0.5, g[2] + 0.5);
        const Vec3 d = body.rest_surface.vertices[i] - centre;
        const std::pair<int, int> site{cell, (d.x() > 0) * 4 + (d.y() > 0) * 2 + (d.z() > 0)};
        const auto it = site_best.find(site);
        if (it == site_best.end() || phi < it->second.first) site_best[site] = {phi, static_cast<int>(i)};
      }
      for (const auto& [site, best] : site_best)
        if (best.first < contact_margin(m, 0)) expected.push_back(contact_key(static_cast<uint32_t>(best.second), 0));
      std::sort(expected.begin(), expected.end());
      MESSAGE(obstacle << ": " << expected.size() << " of " << surface.size() << " vertices within the margin, "
                       << r.candidates << " tested");
      CHECK(!expected.empty());
      CHECK(found == expected);  // both ascending by vertex
      CHECK(r.deepest == doctest::Approx(deepest).epsilon(1e-12));
      CHECK(r.candidates < static_cast<int>(surface.size()));  // the broad phase culled something
      // The brute-force path (every vertex; every triangle of a mesh) gives the same rows.
      RowTable slow;
      add_contact_rows(m, 0, x, velocities(m), {}, slow, ContactSearch::BruteForce);
      REQUIRE(slow.key == rows.key);
      double worst = 0;
      for (int i = 0; i < rows.size(); ++i) worst = std::max(worst, std::abs(slow.value[i] - rows.value[i]));
      for (size_t e = 0; e < rows.jac.size(); ++e) worst = std::max(worst, (slow.jac[e] - rows.jac[e]).norm());
      CHECK(worst < 1e-12);
    }
  }
}

TEST_CASE("contact rows: kept keys keep their rows beyond the margin; keys do not depend on x") {
  const Model m = model_with(kAnalytic[0], R"({"contact_margin": 0})");
  const VecX x = deformed(m, 0.02), v = velocities(m);
  RowTable near, moved;
  add_contact_rows(m, 0, x, v, {}, near);
  REQUIRE(near.size() >= 3);
  // Lift the whole body 1 m off the plane: no row, unless kept.
  VecX lifted = x;
  for (int n = 0; n < m.num_nodes; ++n) lifted[3 * n + 1] += 1;
  add_contact_rows(m, 0, lifted, v, {}, moved);
  CHECK(moved.size() == 0);
  std::vector<uint64_t> keep{near.key[0]};
  add_contact_rows(m, 0, lifted, v, keep, moved);
  REQUIRE(moved.size() == 3);
  CHECK(moved.key[0] == near.key[0]);
  CHECK(moved.key[1] == near.key[1]);
  CHECK(moved.value[0] == doctest::Approx(near.value[0] + 1 * m.obstacles[0].normal.y()));
}

TEST_CASE("contact rows: frictionless obstacles give normal rows only; no obstacle, no work") {
  const Model m = model_with(R"({"type": "plane", "point": [0, -0.2, 0], "friction": 0})");
  RowTable rows;
  add_contact_rows(m, 0, m.rest_x, VecX::Zero(3 * m.num_nodes), {}, rows);
  CHECK(rows.count(RowKind::Contact) > 0);
  CHECK(rows.count(RowKind::Friction) == 0);

  Model none = m;
  none.obstacles.clear();
  rows.clear();
  const ContactRowsResult r = add_contact_rows(none, 0, m.rest_x, VecX::Zero(3 * m.num_nodes), {}, rows);
  CHECK(rows.size() == 0);
  CHECK(r.candidates == 0);
}

TEST_CASE("contact rows: the same table for 1 and 2 threads") {
  for (const std::string& obstacle : obstacles()) {
    const Model m = model_with(obstacle);
    const VecX x = deformed(m, 0.03), v = velocities(m);
    auto build = [&](int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      RowTable rows;
      add_contact_rows(m, 0.1, x, v, {}, rows);
      return rows;
    };
    const RowTable a = build(1), b = build(2);
    CHECK(a.key == b.key);
    CHECK(a.value == b.value);
    CHECK(a.nodes == b.nodes);
    CHECK(a.jac == b.jac);
  }
}
