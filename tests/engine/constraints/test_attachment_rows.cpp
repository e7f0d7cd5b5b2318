// Attachment rows (a grabbed surface point held at a target): values and Jacobians against
// finite differences, on a hex and a tet body.
#include <doctest/doctest.h>

#include <random>

#include "engine/constraints/attachment_rows.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

Model body_model(const char* elements) {
  const std::string text = std::string(R"({"bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}],
    "cell_size": 0.1, "elements": ")") + elements + R"(", "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})";
  return build_model(parse_scene_text(text, "t", "."), [](const std::string&) {});
}

}  // namespace

TEST_CASE("attachment rows: C = p - target per axis, Jacobian = FD of C") {
  for (const char* elements : {"hex", "tet"}) {
    CAPTURE(elements);
    const Model model = body_model(elements);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    VecX x = model.rest_x;
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
    const Attachment a{0, int(model.bodies[0].rest_surface.vertices.size() / 2), Vec3(0.3, 0.2, -0.1)};
    RowTable rows;
    const double gap = add_attachment_rows(model, {a}, x, rows);
    REQUIRE(rows.size() == 3);
    const Vec3 p = attached_point(model, a, x);
    CHECK(gap == doctest::Approx((p - a.target).norm()));
    for (int j = 0; j < 3; ++j) {
      CHECK(rows.value[size_t(j)] == doctest::Approx(p[j] - a.target[j]));
      CHECK(rows.lo[size_t(j)] == -std::numeric_limits<double>::infinity());
      CHECK(rows.hi[size_t(j)] == std::numeric_limits<double>::infinity());
      // C is linear in x: central differences are exact up to round-off (1e-16 / 1e-6).
      for (int k = rows.begin[size_t(j)]; k < rows.begin[size_t(j) + 1]; ++k)
        for (int c = 0; c < 3; ++c) {
          const double eps = 1e-6;
          VecX plus = x, minus = x;
          plus[3 * rows.nodes[size_t(k)] + c] += eps;
          minus[3 * rows.nodes[size_t(k)] + c] -= eps;
          const double fd = (attached_point(model, a, plus)[j] - attached_point(model, a, minus)[j]) / (2 * eps);
          CHECK(std::abs(fd - rows.jac[size_t(k)][c]) < 1e-9);
        }
    }
  }
}

// Solved with the other constraints: a free body, one vertex held 5 cm away, settles with
// the vertex on its target (to the SQP tolerance, contact_tolerance).
TEST_CASE("attachment rows: World holds an attached vertex at its target") {
  const Model model = body_model("hex");
  World world(model);
  const int vertex = 0;
  const Vec3 target = world.state().surface[0][vertex] + Vec3(0, 0.05, 0);
  world.mutable_state().attachments.push_back({0, vertex, target});
  for (int s = 0; s < 20; ++s) REQUIRE(world.step());
  const Vec3 p = attached_point(model, world.state().attachments[0], world.state().x);
  CHECK((p - target).norm() <= model.solver.contact_tolerance * (1 + 1e-9));
  CHECK(world.profile().rows.at("attachment") == 3);
}
