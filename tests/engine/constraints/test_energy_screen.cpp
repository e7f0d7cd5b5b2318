// The energy screen (engine/constraints/energy_screen.hpp): its bound is never below the
// exact Ue / Umax, and a row build that uses it makes the same rows and the same worst value
// as one that evaluates every element.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstring>
#include <limits>
#include <random>

#include "engine/analysis/element_fields.hpp"
#include "engine/assembly/element_kernels.hpp"
#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/energy_screen.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// Paper 000's fig. 3 beam (56 hex along x, Umax 0.1 J), built from its shipped scene.
Model beam_model() {
  const SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_beam_150kPa_U0.1.json");
  return build_model(scene, [](const std::string&) {});
}

// The beam bent in y by `bend` x^3 (curvature 6 bend x: none at its middle, most at its
// ends, so the elements range from unloaded to past their limit), then turned rigidly.
VecX bent(const Model& model, double bend) {
  const Mat3 Q = Eigen::AngleAxisd(0.4, Vec3(0.2, 1, 0.5).normalized()).toRotationMatrix();
  VecX x = model.rest_x;
  for (int n = 0; n < model.num_nodes; ++n) {
    Vec3 p = model.rest_x.segment<3>(3 * n);
    p.y() += bend * p.x() * p.x() * p.x();
    x.segment<3>(3 * n) = Q * p;
  }
  return x;
}

double exact_ratio(const Model& model, const VecX& x, int e) {
  return element_limit_energy(model, e, element_corotated_displacement(model, x, e)) / model.element_Umax[e];
}

std::vector<double> exact_ratios(const Model& model, const VecX& x) {
  std::vector<double> ratio(model.num_elements, 0.0);
  for (int e = 0; e < model.num_elements; ++e)
    if (model.element_Umax[e] > 0) ratio[e] = exact_ratio(model, x, e);
  return ratio;
}

}  // namespace

TEST_CASE("energy screen: the bound is never below the exact ratio, and tight at the reference") {
  const Model model = beam_model();
  const VecX x_ref = bent(model, 0.4);
  const std::vector<double> ratio_ref = exact_ratios(model, x_ref);
  REQUIRE(*std::max_element(ratio_ref.begin(), ratio_ref.end()) > 1.0);  // some past the limit
  EnergyScreen screen;
  record_energy_reference(model, x_ref, ratio_ref, screen);
  // At the reference the bound is the exact ratio, inflated by its round-off allowance.
  for (int e = 0; e < model.num_elements; ++e) {
    const double bound = energy_ratio_bound(model, screen, x_ref, e);
    CHECK(bound >= ratio_ref[e]);
    CHECK(bound <= ratio_ref[e] * (1 + 2e-6) + 2e-12);
  }
  // Moved nodes (random, 1 um to 1 cm) and a rigid turn: never below. The bound's excess is
  // first order in the motion (exact at the reference, Lipschitz terms linear in |dx|), so
  // 100x less motion must shrink it about 100x: at least 50x, beside the 1e-6 allowance.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> widest_gap;
  for (const double scale : {1e-6, 1e-4, 1e-3, 1e-2}) {
    CAPTURE(scale);
    double gap = 0;
    for (int trial = 0; trial < 20; ++trial) {
      const Mat3 turn = Eigen::AngleAxisd(scale * u(rng), Vec3(u(rng), u(rng), 1).normalized()).toRotationMatrix();
      VecX x = x_ref;
      for (int n = 0; n < model.num_nodes; ++n)
        x.segment<3>(3 * n) = turn * x_ref.segment<3>(3 * n) + scale * Vec3(u(rng), u(rng), u(rng));
      int below = 0;
      for (int e = 0; e < model.num_elements; ++e) {
        if (model.element_Umax[e] <= 0) continue;
        const double exact = exact_ratio(model, x, e), bound = energy_ratio_bound(model, screen, x, e);
        if (bound < exact) ++below;
        gap = std::max(gap, bound - exact - 1e-6 * exact);
      }
      CHECK(below == 0);
    }
    widest_gap.push_back(gap);
  }
  CHECK(widest_gap[0] * 50 < widest_gap[1]);
}

TEST_CASE("energy screen: an inverted element is never screened") {
  const Model model = beam_model();
  const VecX x_ref = bent(model, 0.1);
  EnergyScreen screen;
  record_energy_reference(model, x_ref, exact_ratios(model, x_ref), screen);
  // Element 0's inner tetrahedron (nodes 0, 3, 5, 6) turned inside out: node 0 pushed
  // through the opposite face.
  VecX x = x_ref;
  const std::array<Vec3, 8> nodes = gather_element_nodes(model, x_ref, 0).x;
  const Vec3 face_center = (nodes[3] + nodes[5] + nodes[6]) / 3;
  const int node0 = model.element_nodes[0][0];
  x.segment<3>(3 * node0) = nodes[0] + 2.5 * (face_center - nodes[0]);
  REQUIRE(hex8_inner_deformation_gradient(gather_element_nodes(model, x, 0).x,
                                          model.references[model.element_reference[0]].cell_size)
              .determinant() < 0);
  CHECK(energy_ratio_bound(model, screen, x, 0) == std::numeric_limits<double>::infinity());
}

TEST_CASE("energy screen: the same rows and worst value as evaluating every element") {
  const Model model = beam_model();
  const VecX x_ref = bent(model, 0.4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX x = x_ref;
  for (int i = 0; i < x.size(); ++i) x[i] += 1e-4 * u(rng);
  const double margin = 0.05;
  const std::vector<uint64_t> keep;
  EnergyScreen screen;
  RowTable reference_rows, screened_rows, plain_rows;
  add_energy_limit_rows(model, x_ref, margin, keep, reference_rows, &screen);  // records x_ref
  REQUIRE(screen.valid);
  const double screened_worst = add_energy_limit_rows(model, x, margin, keep, screened_rows, &screen);
  const double plain_worst = add_energy_limit_rows(model, x, margin, keep, plain_rows);
  CHECK(screen.screened > 0);  // the bound left some elements out...
  CHECK(screened_rows.size() > 0);  // ...and some still made rows
  CHECK(screened_worst == plain_worst);
  REQUIRE(screened_rows.size() == plain_rows.size());
  CHECK(screened_rows.key == plain_rows.key);
  CHECK(screened_rows.value == plain_rows.value);
  CHECK(screened_rows.nodes == plain_rows.nodes);
  REQUIRE(screened_rows.jac.size() == plain_rows.jac.size());
  CHECK(std::memcmp(screened_rows.jac.data(), plain_rows.jac.data(), sizeof(Vec3) * plain_rows.jac.size()) == 0);
}
