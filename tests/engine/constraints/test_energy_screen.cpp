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
#include "engine/math/polar_rotation.hpp"
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

// x with every coordinate moved by up to `amplitude`, uniformly at random.
VecX shaken(const VecX& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX out = x;
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] += amplitude * u(rng);
  return out;
}

VecX translated(const VecX& x, const Vec3& by) {
  VecX out = x;
  for (Eigen::Index n = 0; n < x.size() / 3; ++n) out.segment<3>(3 * n) += by;
  return out;
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
    // ... plus the round-off term it adds: 1024 eps lambda_max (|x| + |X|)^2 / Umax, here
    // with the element's nodes within 2 m of the origin and 3 m of their rest places.
    if (model.element_Umax[e] > 0) {
      const double root_lambda = model.references[model.element_reference[e]].root_lambda_max;
      const double round_off = 1024 * std::numeric_limits<double>::epsilon() * root_lambda * root_lambda *
                               std::pow(2 * std::sqrt(8.0) + 3 * std::sqrt(8.0), 2) / model.element_Umax[e];
      CHECK(bound <= ratio_ref[e] * (1 + 2e-6) + round_off);
    }
  }
  // Moved nodes (random, 1 um to 1 cm) and a rigid turn: never below. The bound's excess is
  // first order in the motion (exact at the reference, Lipschitz terms linear in |dx|), so
  // 100x less motion shrinks it 100x up to second-order terms, which at 1e-4 m (strains of
  // 1e-3) are under 1 % of it: less than 50x would mean a term that does not vanish.
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

TEST_CASE("energy screen: the polar factor's change is within its bound, which is tight") {
  // F_ref = I and F = Q, a rotation: |Q - I|_F against 2 |Q - I|_F / (2/3 + 2/3), the
  // sigma_min bounds of I and Q being 2 det / |.|_F^2 = 2/3: the bound is 1.5x the change,
  // so a factor of 2 too small anywhere in it fails here.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Mat3 Q = Eigen::AngleAxisd(3 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    const double change = (Q - Mat3::Identity()).norm(), bound = polar_change_bound(Q, Mat3::Identity());
    CHECK(bound >= change);
    CHECK(bound == doctest::Approx(1.5 * change).epsilon(1e-12));
  }
  // Random well-conditioned F and a nearby F_ref: never below the actual change.
  for (int trial = 0; trial < 200; ++trial) {
    Mat3 F_ref = Mat3::Identity(), dF;
    for (int i = 0; i < 9; ++i) F_ref(i / 3, i % 3) += 0.3 * u(rng), dF(i / 3, i % 3) = u(rng);
    const Mat3 F = F_ref + std::pow(10.0, -4 + 3 * (u(rng) + 1) / 2) * dF;
    const double bound = polar_change_bound(F, F_ref);
    if (bound == std::numeric_limits<double>::infinity()) continue;  // not well conditioned
    CHECK(bound >= (polar_rotation(F) - polar_rotation(F_ref)).norm());
  }
  // Near-singular F: no bound (the polar code may take its SVD there).
  Mat3 flat = Mat3::Identity();
  flat(2, 2) = 1e-4;
  CHECK(polar_change_bound(flat, Mat3::Identity()) == std::numeric_limits<double>::infinity());
}

TEST_CASE("energy screen: the bound holds far from the origin, where round-off grows") {
  // u = R^T x - X carries the body's translation, which Ke annihilates only to round-off:
  // 1 km away the exact value's round-off is far above the bound's 1e-6 relative allowance.
  const Model model = beam_model();
  for (const double distance : {1e2, 1e3}) {
    CAPTURE(distance);
    const Vec3 away(distance, -0.5 * distance, 0.3 * distance);
    const VecX x_ref = translated(bent(model, 0.4), away);
    EnergyScreen screen;
    record_energy_reference(model, x_ref, exact_ratios(model, x_ref), screen);
    const VecX x = shaken(x_ref, 1e-5, 4);
    int below = 0;
    for (int e = 0; e < model.num_elements; ++e)
      if (model.element_Umax[e] > 0 && energy_ratio_bound(model, screen, x, e) < exact_ratio(model, x, e)) ++below;
    CHECK(below == 0);
  }
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
  // Bent past the limit (some rows), and bent gently (every element screened, no row: the
  // worst value then comes from the screened ones); a kept row of an element far below its
  // limit stays.
  const Model model = beam_model();
  for (const double bend : {0.4, 0.02}) {
  CAPTURE(bend);
  const VecX x_ref = bent(model, bend);
  const VecX x = shaken(x_ref, 1e-4, 5);
  const double margin = 0.05;
  const std::vector<double> ratio = exact_ratios(model, x);
  const int quiet = static_cast<int>(std::min_element(ratio.begin(), ratio.end(), [&](double a, double b) {
                                       return (a > 0 ? a : 1e9) < (b > 0 ? b : 1e9);
                                     }) - ratio.begin());
  const std::vector<uint64_t> keep = {row_key(RowKind::Energy, static_cast<uint32_t>(quiet))};
  EnergyScreen screen;
  RowTable reference_rows, screened_rows, plain_rows;
  add_energy_limit_rows(model, x_ref, margin, keep, reference_rows, &screen);  // records x_ref
  REQUIRE(screen.valid);
  const double screened_worst = add_energy_limit_rows(model, x, margin, keep, screened_rows, &screen);
  const double plain_worst = add_energy_limit_rows(model, x, margin, keep, plain_rows);
  CHECK(screen.screened > 0);  // the bound left elements out
  CHECK(std::find(plain_rows.key.begin(), plain_rows.key.end(), keep[0]) != plain_rows.key.end());
  if (bend > 0.1) {
    CHECK(plain_rows.size() > 1);  // rows beside the kept one
    CHECK(screened_worst == plain_worst);
  } else {
    // Nothing near its limit: the worst value may be a bound, above the exact one and
    // below -margin like it.
    CHECK(plain_worst <= screened_worst);
    CHECK(screened_worst <= -margin);
  }
  REQUIRE(screened_rows.size() == plain_rows.size());
  CHECK(screened_rows.key == plain_rows.key);
  CHECK(screened_rows.value == plain_rows.value);
  CHECK(screened_rows.nodes == plain_rows.nodes);
  REQUIRE(screened_rows.jac.size() == plain_rows.jac.size());
  CHECK(std::memcmp(screened_rows.jac.data(), plain_rows.jac.data(), sizeof(Vec3) * plain_rows.jac.size()) == 0);
  }
}

TEST_CASE("energy screen: kept across builds along a path, the same rows and worst value at every point") {
  // One screen through 40 builds along a motion that bends the beam past its limit and back
  // while it turns (elements come to and leave their limits; the references of elements
  // evaluated move with them): each build matches a build that evaluates every element.
  const Model model = beam_model();
  const double margin = 0.05;
  EnergyScreen screen;
  long screened = 0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 40; ++k) {
    CAPTURE(k);
    // Bent from straight to 0.3 (the ends past their limit) and partly back; turning 1e-4
    // rad a build (a body near rest: the bound grows with the motion since the reference).
    const double bend = 0.3 * std::sin(0.06 * k);
    const Mat3 turn = Eigen::AngleAxisd(1e-4 * k, Vec3(0, 0, 1)).toRotationMatrix();
    VecX x = bent(model, bend);
    for (int n = 0; n < model.num_nodes; ++n)
      x.segment<3>(3 * n) = turn * x.segment<3>(3 * n) + 1e-6 * Vec3(u(rng), u(rng), u(rng));
    const std::vector<uint64_t> keep;
    RowTable screened_rows, plain_rows;
    const double screened_worst = add_energy_limit_rows(model, x, margin, keep, screened_rows, &screen);
    const double plain_worst = add_energy_limit_rows(model, x, margin, keep, plain_rows);
    if (k > 0) screened += screen.screened;
    if (plain_worst > -margin) CHECK(screened_worst == plain_worst);
    else CHECK((plain_worst <= screened_worst && screened_worst <= -margin));
    REQUIRE(screened_rows.size() == plain_rows.size());
    CHECK(screened_rows.key == plain_rows.key);
    CHECK(screened_rows.value == plain_rows.value);
    REQUIRE(screened_rows.jac.size() == plain_rows.jac.size());
    // Straight (k = 0) or barely bent, no row: memcmp may not be given empty storage's null.
    if (!plain_rows.jac.empty())
      CHECK(std::memcmp(screened_rows.jac.data(), plain_rows.jac.data(), sizeof(Vec3) * plain_rows.jac.size()) == 0);
  }
  CHECK(screened > 0);  // the kept references did leave elements out
}

TEST_CASE("energy screen: an element evaluated exactly becomes its own reference") {
  // Recorded at x_ref, then a build at x far from it (a 1 cm shake: the bound is loose, the
  // elements are evaluated): the bound at x is then the exact value there, up to its
  // round-off allowance.
  const Model model = beam_model();
  const VecX x_ref = bent(model, 0.02);
  EnergyScreen screen;
  record_energy_reference(model, x_ref, exact_ratios(model, x_ref), screen);
  const VecX x = shaken(x_ref, 1e-2, 12);
  RowTable rows;
  add_energy_limit_rows(model, x, 0.05, {}, rows, &screen);
  int loose = 0;
  for (int e = 0; e < model.num_elements; ++e) {
    if (model.element_Umax[e] <= 0) continue;
    const double exact = exact_ratio(model, x, e), bound = energy_ratio_bound(model, screen, x, e);
    CHECK(bound >= exact);
    // Tight: 1e-6 relative plus the round-off allowance, as at the reference in the first
    // test (nodes within 2 m of the origin and 3 m of their rest places).
    const double root_lambda = model.references[model.element_reference[e]].root_lambda_max;
    const double round_off = 1024 * std::numeric_limits<double>::epsilon() * root_lambda * root_lambda *
                             std::pow(2 * std::sqrt(8.0) + 3 * std::sqrt(8.0), 2) / model.element_Umax[e];
    if (bound > exact * (1 + 2e-6) + round_off) ++loose;
  }
  // Those screened at x keep their reference at x_ref (a loose bound, still below 0.95);
  // every other one is tight now.
  CHECK(loose <= screen.screened);
  CHECK(screen.screened < model.num_elements);
}
