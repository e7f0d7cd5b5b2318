// Body-vs-body contact rows (engine/constraints/body_contact_rows.cpp): Jacobians over both
// bodies' nodes against finite differences, the broad phase and Embree against the brute
// force path, one entry per node, zero net impulse per row, thread-count independence.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "engine/constraints/body_contact_rows.hpp"

using namespace sinew;

namespace {

// Two 0.25 m spheres 0.45 m apart (overlapping by 5 cm), on 0.1 m cells.
Model two_spheres() {
  const std::string text = R"({"h": 0.01, "solver": {"contact_margin": 0.03, "body_friction": 0.3},
    "bodies": [{"name": "a", "shape": [{"type": "sphere", "radius": 0.25}], "cell_size": 0.1,
                "surface_resolution": 0.06, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}},
               {"name": "b", "shape": [{"type": "sphere", "radius": 0.25}], "cell_size": 0.1,
                "transform": {"translate": [0.45, 0.03, -0.02]},
                "surface_resolution": 0.06, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})";
  return build_model(parse_scene_text(text, "two spheres", "."), [](const std::string&) {});
}

VecX deformed(const Model& m, double amount) {
  VecX x = m.rest_x;
  for (int n = 0; n < m.num_nodes; ++n) {
    const Vec3 X = m.rest_x.segment<3>(3 * n);
    x.segment<3>(3 * n) += amount * Vec3(std::sin(7 * X.y()), std::cos(5 * X.z()), std::sin(6 * X.x() + 1));
  }
  return x;
}

VecX velocities(const Model& m) {
  VecX v(3 * m.num_nodes);
  for (int i = 0; i < v.size(); ++i) v[i] = std::sin(0.37 * i + 0.2);
  return v;
}

uint32_t vertex_of(uint64_t key) { return static_cast<uint32_t>((key >> 24) & ((uint64_t(1) << 36) - 1)); }
uint32_t partner_of(uint64_t key) { return static_cast<uint32_t>(key & 0xFFFFFF); }

double row_value(const Model& m, const VecX& x, const VecX& v, uint64_t key) {
  static BodySurfaces surfaces;  // refitted at each call, not rebuilt
  RowTable rows;
  const uint32_t partner = (key >> 60) == uint64_t(RowKind::Friction) ? partner_of(key) / 2 : partner_of(key);
  add_body_contact_rows(m, x, v, {contact_key(vertex_of(key), partner)}, surfaces, rows);
  for (int i = 0; i < rows.size(); ++i)
    if (rows.key[i] == key) return rows.value[i];
  FAIL("row disappeared");
  return 0;
}

}  // namespace

TEST_CASE("body contact rows: Jacobians over both bodies are the derivatives of the row values") {
  const Model m = two_spheres();
  const VecX x = deformed(m, 0.01), v = velocities(m);
  BodySurfaces surfaces;
  RowTable rows;
  const ContactRowsResult r = add_body_contact_rows(m, x, v, {}, surfaces, rows);
  REQUIRE(rows.count(RowKind::Contact) > 10);
  CHECK(r.deepest > 0.01);  // the spheres overlap
  double worst = 0;
  int checked = 0, both_bodies = 0;
  const int stride = std::max(1, rows.size() / 12);  // about 12 rows, normal and friction
  for (int i = 0; i < rows.size(); i += stride) {
    const bool normal = rows.kind[i] == RowKind::Contact;
    std::set<int> bodies;
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e) {
      bodies.insert(m.node_body[rows.nodes[e]]);
      for (int a = 0; a < 3; ++a) {
        // Normal rows: central difference of phi over a node's position (step 1e-7 m; phi is
        // smooth while the nearest feature stays, error ~1e-7 / |p - c|). Friction rows:
        // the value h t . (v_p - v_c) is linear in v.
        const double step = 1e-7;
        VecX xp = x, xm = x, vp = v, vm = v;
        (normal ? xp : vp)[3 * rows.nodes[e] + a] += step;
        (normal ? xm : vm)[3 * rows.nodes[e] + a] -= step;
        const double d = (row_value(m, xp, vp, rows.key[i]) - row_value(m, xm, vm, rows.key[i])) / (2 * step);
        worst = std::max(worst, std::abs(d - (normal ? 1.0 : m.h) * rows.jac[e][a]));
        ++checked;
      }
    }
    both_bodies += bodies.size() == 2;
  }
  MESSAGE(rows.count(RowKind::Contact) << " contacts, " << checked << " derivatives, worst error " << worst);
  CHECK(both_bodies > 0);
  CHECK(worst < 1e-5);
}

TEST_CASE("body contact rows: each node once per row, and no net impulse (sum of jac = 0)") {
  const Model m = two_spheres();
  BodySurfaces surfaces;
  RowTable rows;
  add_body_contact_rows(m, deformed(m, 0.01), velocities(m), {}, surfaces, rows);
  REQUIRE(rows.size() > 0);
  double worst = 0;
  for (int i = 0; i < rows.size(); ++i) {
    std::set<int> nodes(rows.nodes.begin() + rows.begin[i], rows.nodes.begin() + rows.begin[i + 1]);
    REQUIRE(static_cast<int>(nodes.size()) == rows.begin[i + 1] - rows.begin[i]);
    // Weights and barycentrics each sum to one: sum_n w_n d - sum_k beta_k sum_m w_km d = 0,
    // so a contact impulse pushes the two bodies equally and oppositely.
    Vec3 sum = Vec3::Zero();
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e) sum += rows.jac[e];
    worst = std::max(worst, sum.norm());
  }
  CHECK(worst < 1e-12);
}

TEST_CASE("body contact rows: broad phase and BVH give the rows of the brute-force path") {
  const Model m = two_spheres();
  for (double amount : {0.0, 0.02}) {
    const VecX x = deformed(m, amount), v = velocities(m);
    BodySurfaces fast_surfaces, slow_surfaces;
    RowTable fast, slow;
    const ContactRowsResult r = add_body_contact_rows(m, x, v, {}, fast_surfaces, fast);
    add_body_contact_rows(m, x, v, {}, slow_surfaces, slow, ContactSearch::BruteForce);
    REQUIRE(fast.key == slow.key);
    double worst = 0;
    for (int i = 0; i < fast.size(); ++i) worst = std::max(worst, std::abs(fast.value[i] - slow.value[i]));
    MESSAGE(fast.count(RowKind::Contact) << " contacts; " << r.candidates << " vertices tested of "
                                         << m.bodies[0].embedding.cell.size() + m.bodies[1].embedding.cell.size());
    CHECK(worst < 1e-12);
    CHECK(fast.count(RowKind::Contact) > 0);
  }
}

TEST_CASE("body contact rows: the same rows for 1 and 2 threads; nothing for bodies apart") {
  const Model m = two_spheres();
  const VecX x = deformed(m, 0.02), v = velocities(m);
  auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BodySurfaces surfaces;
    RowTable rows;
    add_body_contact_rows(m, x, v, {}, surfaces, rows);
    return rows;
  };
  const RowTable one = build(1), two = build(2);
  CHECK(one.key == two.key);
  CHECK(one.value == two.value);
  CHECK(one.jac == two.jac);

  VecX apart = x;
  for (int n = m.bodies[1].node_offset; n < m.num_nodes; ++n) apart[3 * n] += 1.0;
  BodySurfaces surfaces;
  RowTable rows;
  const ContactRowsResult r = add_body_contact_rows(m, apart, v, {}, surfaces, rows);
  CHECK(rows.size() == 0);
  CHECK(r.candidates == 0);  // culled before any distance query
  CHECK(surfaces.mesh.empty());  // and no surface was even built
}
