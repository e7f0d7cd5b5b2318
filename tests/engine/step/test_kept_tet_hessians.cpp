// Kept tet Hessians (solver.hessian_reuse_tolerance, kept_tet_hessians.hpp): the Hessian pass
// with kept blocks adds to the system's values what the full pass adds, at the F each tet's
// blocks were formed at. Where every tet either moved past the tolerance or not at all, that
// is the full pass at the new positions, up to the round-off of the kept sum's updates; the
// energies and gradient are always the full pass's, bit for bit. In a simulation the kept
// Hessians skip most of a resting body's work, and Newton still meets its tolerances.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "engine/assembly/element_kernels.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/assembly/kept_tet_hessians.hpp"
#include "engine/scene/scene.hpp"
#include "engine/step/hyperelastic_derivatives.hpp"
#include "engine/world.hpp"
#include "tests/engine/step/snh_landing_box.hpp"
#include "tests/support/mixed_hyperelastic_model.hpp"

using namespace sinew;

namespace {

struct Pass {
  std::vector<double> energy, force2, values;
  VecX gradient;
};

// The Newton assembly's pass at x into zeroed values: every Hessian formed (kept null), or with kept ones.
Pass hessian_pass(const Model& model, const VecX& x, KeptTetHessians* kept = nullptr, double tolerance = 0) {
  Pass p;
  p.values.assign(model.pattern.matrix.nonZeros(), 0.0);
  std::vector<Vec3> node_gradients;
  hyperelastic_derivatives(model, x, false, p.energy, p.force2, p.gradient, p.values.data(), node_gradients, kept,
                           tolerance);
  return p;
}

bool kept_kind(const Model& model, int e) {
  const Body& body = model.bodies[model.element_body[e]];
  return body.hyperelastic && body.hyperelastic->as_invariant() && element_node_count(model, e) == 4;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double a : v) m = std::max(m, std::abs(a));
  return m;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

}  // namespace

TEST_CASE("kept tet Hessians: the full pass where tets moved past the tolerance or not at all") {
  const Model model = test::mixed_hyperelastic_model();
  int kept_tets = 0;
  for (int e = 0; e < model.num_elements; ++e) kept_tets += kept_kind(model, e);
  REQUIRE(kept_tets > 0);
  REQUIRE(kept_tets < model.num_elements);  // hexes too, formed at every pass
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.005, 0.005);
  VecX x = model.rest_x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  const double tolerance = 1e-3;
  KeptTetHessians kept;

  // First pass: every tet formed, each value receiving the same products in the same order
  // (the schedule's colours; 0 + c K - 0 = c K): the full pass bit for bit.
  Pass with_kept = hessian_pass(model, x, &kept, tolerance);
  Pass full = hessian_pass(model, x);
  CHECK(kept.formed == kept_tets);
  CHECK(with_kept.values == full.values);
  CHECK(with_kept.energy == full.energy);

  // Rounds of moves: a few nodes by up to 5 mm (F changes by ~0.1 in their tets, past the
  // tolerance), the others not at all (their tets' F the same bits).
  for (int round = 0; round < 6; ++round) {
    CAPTURE(round);
    std::set<int> moved;
    std::uniform_int_distribution<int> pick(0, model.num_nodes - 1);
    while (moved.size() < 6) moved.insert(pick(rng));
    for (int n : moved)
      for (int k = 0; k < 3; ++k) x[3 * n + k] += u(rng);
    long expected = 0;  // kept tets with a moved node
    for (int e = 0; e < model.num_elements; ++e) {
      if (!kept_kind(model, e)) continue;
      bool touches = false;
      for (int a = 0; a < 4; ++a) touches = touches || moved.count(model.element_nodes[e][a]) > 0;
      expected += touches;
    }
    with_kept = hessian_pass(model, x, &kept, tolerance);
    full = hessian_pass(model, x);
    CHECK(kept.formed == expected);
    // The energies and gradient: the same function of x either way.
    CHECK(with_kept.energy == full.energy);
    CHECK(with_kept.force2 == full.force2);
    CHECK(with_kept.gradient == full.gradient);
    // The values: the same terms summed, less and plus earlier ones. Each value sums the
    // blocks of the at most 24 tets around an edge (the lattice's), each added once, and
    // here at most 7 times changed: ~ (24 + 2 * 7 * 24) additions, each off by at most u of
    // a partial sum that can reach ~2x the largest value: within 2e-13 (~900 u) of it.
    const double scale = max_abs(full.values);
    CHECK(max_difference(with_kept.values, full.values) <= 2e-13 * scale);
  }
}

TEST_CASE("kept tet Hessians: moves within the tolerance keep every Hessian") {
  const Model model = test::mixed_hyperelastic_model();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.005, 0.005);
  VecX x = model.rest_x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  KeptTetHessians kept;
  const Pass first = hessian_pass(model, x, &kept, 1e-3);
  // Every node by up to 1e-6 m: F by at most ~4e-5 in these 5 cm cells (|dN| ~ 1 / 5 cm times
  // four nodes' moves), within the tolerance.
  std::uniform_real_distribution<double> tiny(-1e-6, 1e-6);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += tiny(rng);
  const Pass second = hessian_pass(model, x, &kept, 1e-3);
  const Pass full = hessian_pass(model, x);
  CHECK(kept.formed == 0);
  CHECK(second.gradient == full.gradient);
  CHECK(second.energy == full.energy);
  // The kept sum did not change (nothing formed), so where no hex adds terms the values are
  // the first pass's, bit for bit.
  std::vector<char> hex_entry(first.values.size(), 0);
  for (int e = 0; e < model.num_elements; ++e) {
    if (kept_kind(model, e) || !model.bodies[model.element_body[e]].hyperelastic) continue;
    const int n = element_node_count(model, e);
    for (int i = 0; i < 3 * n * n; ++i)
      if (const int at = model.pattern.element_scatter[model.pattern.scatter_begin[e] + i]; at >= 0)
        for (int r = 0; r < 3; ++r) hex_entry[at + r] = 1;
  }
  long compared = 0;
  for (size_t i = 0; i < first.values.size(); ++i) {
    if (hex_entry[i] || first.values[i] == 0) continue;
    CHECK(second.values[i] == first.values[i]);
    ++compared;
  }
  CHECK(compared > 0);
  // With a tolerance of 0 the same move forms every tet again: the full pass's values.
  const Pass strict = hessian_pass(model, x, &kept, 0.0);
  long kept_tets = 0;
  for (int e = 0; e < model.num_elements; ++e) kept_tets += kept_kind(model, e);
  CHECK(kept.formed == kept_tets);
  CHECK(max_difference(strict.values, full.values) <= 2e-13 * max_abs(full.values));
}

TEST_CASE("kept tet Hessians: another h or pattern drops what is held") {
  KeptTetHessians kept;
  kept.prepare(3, 10, 1e-4);
  CHECK(kept.blocks.empty());  // none until some element keeps its Hessian
  kept.allocate_blocks();
  kept.kept[1] = 1;
  kept.values[2] = 5;
  kept.prepare(3, 10, 1e-4);  // the same: kept
  CHECK(kept.kept[1] == 1);
  CHECK(kept.values[2] == 5);
  kept.prepare(3, 10, 4e-4);  // another h^2: the blocks are of another matrix
  CHECK(kept.kept[1] == 0);
  CHECK(kept.values.empty());
  kept.allocate_blocks();
  CHECK(kept.values[2] == 0);
  kept.kept[1] = 1;
  kept.prepare(3, 12, 4e-4);  // another pattern
  kept.allocate_blocks();
  CHECK(kept.kept[1] == 0);
  CHECK(kept.values.size() == 12);
  const Mat3 F = Mat3::Identity();
  CHECK(kept.needs_forming(1, F, 1.0));  // none held
  kept.kept[1] = 1;
  kept.F[1] = F;
  CHECK_FALSE(kept.needs_forming(1, F, 0.0));
  Mat3 moved = F;
  moved(2, 1) += 1e-3;
  CHECK_FALSE(kept.needs_forming(1, moved, 1e-3));
  CHECK(kept.needs_forming(1, moved, 0.9e-3));
  moved(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK(kept.needs_forming(1, moved, 1.0));
}

namespace {

World snh_box(int newton_iterations, double reuse_tolerance) {
  return test::snh_landing_box("\"newton_max_iterations\": " + std::to_string(newton_iterations) +
                               ", \"refactor_interval\": 8, \"sleep_steps\": 0, \"hessian_reuse_tolerance\": " +
                               std::to_string(reuse_tolerance));
}

int stat(const StepProfile& profile, const char* name) { return test::iteration_count(profile, name); }

}  // namespace

TEST_CASE("kept tet Hessians: a landed box keeps its Hessians, at the accuracy of forming them") {
  // One Newton iteration a step (the real-time setting), against Newton converged (to 1e-6,
  // up to 30 iterations) with every Hessian formed.
  World reference = snh_box(30, 0), strict = snh_box(1, 0), reuse = snh_box(1, 1e-3);
  const int tets = reuse.model().num_elements;
  double worst_strict = 0, worst_reuse = 0, sum_strict = 0, sum_reuse = 0;
  long formed_at_rest = 0;
  for (int step = 0; step < 120; ++step) {
    REQUIRE(reference.step());
    REQUIRE(strict.step());
    REQUIRE(reuse.step());
    if (step >= 80) formed_at_rest += stat(reuse.profile(), "newton_hessians_formed");
    const double e_strict = (strict.state().x - reference.state().x).cwiseAbs().maxCoeff();
    const double e_reuse = (reuse.state().x - reference.state().x).cwiseAbs().maxCoeff();
    worst_strict = std::max(worst_strict, e_strict), worst_reuse = std::max(worst_reuse, e_reuse);
    sum_strict += e_strict, sum_reuse += e_reuse;
  }
  MESSAGE("distance from the converged run: worst " << worst_strict << " m forming every Hessian, " << worst_reuse
                                                    << " m keeping them; mean " << sum_strict / 120 << " vs "
                                                    << sum_reuse / 120 << " m; Hessians formed in steps 80-119: "
                                                    << formed_at_rest << " of " << 40 * tets);
  // Landed by step 80 (it falls 5 cm): its F moves by far less than 1e-3 a step, so the
  // resting box forms almost no Hessian (forming them all: 40 x tets).
  CHECK(formed_at_rest <= 40 * tets / 100);
  // A Hessian within 1e-3 of F (its own change with F is of that order, relative) perturbs
  // each Newton direction by ~1e-3 relative, far below the error one Newton iteration a step
  // leaves against converged steps: that error stays within 5 % of forming every Hessian's.
  CHECK(worst_reuse <= 1.05 * worst_strict);
  CHECK(sum_reuse <= 1.05 * sum_strict);
  // And one iteration a step stays within 1 % of the box's length (0.3 m) of the converged
  // steps through the landing (2.8e-4 m; Newton's model handed to the constraint stage at the
  // wrong iterate, a slip caught by the surface error before it was committed, left 4.7e-3 m).
  CHECK(worst_strict <= 0.01 * 0.3);
}

TEST_CASE("kept tet Hessians: Newton converged meets its tolerance and finds the same steps") {
  World strict = snh_box(30, 0), reuse = snh_box(30, 1e-3);
  World tight = test::snh_landing_box(
      "\"newton_max_iterations\": 60, \"newton_tolerance\": 1e-10, \"refactor_interval\": 8, \"sleep_steps\": 0, "
      "\"hessian_reuse_tolerance\": 0");
  long newton_strict = 0, newton_reuse = 0;
  for (int step = 0; step < 120; ++step) {
    REQUIRE(strict.step());
    REQUIRE(reuse.step());
    REQUIRE(tight.step());
    CAPTURE(step);
    // The gradient is exact either way: each step ends within Newton's tolerance (1e-6 of
    // the step's scale) before its cap of 30.
    CHECK(stat(reuse.profile(), "newton") < 30);
    CHECK(reuse.profile().violation.at("newton_residual") <= 1e-6);
    newton_strict += stat(strict.profile(), "newton");
    newton_reuse += stat(reuse.profile(), "newton");
  }
  // How far Newton's tolerance (1e-6 of each step's scale) lets a run stray is measured by a
  // run converged to 1e-10 (strict_off). Kept Hessians change only the path of the Newton
  // iterations (by ~1e-3 relative, the tolerance on F), not the equations they solve: the
  // run that keeps them is as near the converged one (within 5 %, as for one iteration
  // above), and the two runs, stopping within the same tolerance of the same solutions
  // along paths that nearly coincide, nearer each other than either is to it.
  const double distance = (strict.state().x - reuse.state().x).cwiseAbs().maxCoeff();
  const double strict_off = (strict.state().x - tight.state().x).cwiseAbs().maxCoeff();
  const double reuse_off = (reuse.state().x - tight.state().x).cwiseAbs().maxCoeff();
  MESSAGE("Newton iterations " << newton_strict << " forming every Hessian, " << newton_reuse
                               << " keeping them; distance " << distance << " m; from Newton to 1e-10: "
                               << strict_off << " and " << reuse_off << " m");
  REQUIRE(strict_off > 0);
  CHECK(reuse_off <= 1.05 * strict_off);
  CHECK(distance <= strict_off);
  // Kept Hessians serve only where a projected one is wanted; near convergence Newton forms
  // the exact Hessian whole, so the iterations barely change (at most one more every 10 steps).
  CHECK(newton_reuse <= newton_strict + 12);
}

TEST_CASE("kept tet Hessians: blocks replaced by far smaller ones are summed anew") {
  // One element whose 48 block columns go to values 0-143 in order.
  std::vector<int> scatter(48), begin = {0, 48};
  for (int i = 0; i < 48; ++i) scatter[i] = 3 * i;
  for (const bool avx2 : {true, false}) {
    CAPTURE(avx2);
    std::optional<BaselineKernelsOnly> baseline;
    if (!avx2) baseline.emplace();
    KeptTetHessians kept;
    kept.prepare(1, 144, 1.0);
    kept.allocate_blocks();
    std::array<double, 144> large, small;
    large.fill(1e20);
    small.fill(1.1);
    CHECK_FALSE(kept.replace(0, Mat3::Identity(), large, scatter.data()));
    CHECK(kept.values[7] == 1e20);
    const bool after_larger = kept.replace(0, Mat3::Identity(), small, scatter.data());
    // 0 + 1e20 + (1.1 - 1e20) = 0: the large blocks' round-off is all that is left.
    CHECK(kept.values[7] == 0.0);
    REQUIRE(after_larger);
    kept.rebuild(scatter, begin);
    for (double v : kept.values) CHECK(v == 1.1);
    // A change of at most 1e4 times leaves the sum as it is.
    std::array<double, 144> medium;
    medium.fill(1.1e4);
    CHECK_FALSE(kept.replace(0, Mat3::Identity(), medium, scatter.data()));
    CHECK_FALSE(kept.replace(0, Mat3::Identity(), small, scatter.data()));
  }
}

TEST_CASE("kept tet Hessians: the pass that writes the values whole equals the one that adds to zeros") {
  // Every hyperelastic element a one-point invariant tet (the SNH box of the tests below).
  const World world = snh_box(1, 1e-3);
  const Model& model = world.model();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.004, 0.004);
  VecX x = model.rest_x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  KeptTetHessians adding, writing;
  REQUIRE(keeps_every_hessian(model, writing));
  for (int round = 0; round < 3; ++round) {
    CAPTURE(round);
    Pass added = hessian_pass(model, x, &adding, 1e-3);
    Pass written;
    written.values.assign(model.pattern.matrix.nonZeros(), std::numeric_limits<double>::quiet_NaN());
    std::vector<Vec3> node_gradients;
    hyperelastic_derivatives(model, x, false, written.energy, written.force2, written.gradient, written.values.data(),
                             node_gradients, &writing, 1e-3, true);
    // 0 + k = k: the same bits, every value written (none left NaN).
    CHECK(written.values == added.values);
    CHECK(written.gradient == added.gradient);
    for (int n = 0; n < model.num_nodes; n += 3)
      for (int k = 0; k < 3; ++k) x[3 * n + k] += 10 * u(rng);
  }
}

TEST_CASE("kept tet Hessians: the same states on 1 and 2 threads") {
  VecX x[2];
  long formed[2] = {0, 0};
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    World world = snh_box(1, 1e-3);
    for (int step = 0; step < 60; ++step) {
      REQUIRE(world.step());
      formed[threads - 1] += stat(world.profile(), "newton_hessians_formed");
    }
    x[threads - 1] = world.state().x;
    // Hessians were kept (fewer formed than 60 steps of every tet) and formed afresh.
    CHECK(formed[threads - 1] > 0);
    CHECK(formed[threads - 1] < 60L * world.model().num_elements);
  }
  CHECK(formed[0] == formed[1]);
  CHECK(x[0] == x[1]);
}

TEST_CASE("kept tet Hessians: the test for far smaller blocks reads every value's magnitude and passes over NaN") {
  // replace() compares the largest magnitude of the blocks held with that of the new ones
  // (more than 1e4 times larger: the sum is summed anew). One outstanding value at each of
  // the 144 positions in turn, negative, with a NaN elsewhere, by the AVX2 and scalar kernels.
  std::vector<int> scatter(48);
  for (int i = 0; i < 48; ++i) scatter[i] = 3 * i;
  for (const bool avx2 : {true, false}) {
    CAPTURE(avx2);
    std::optional<BaselineKernelsOnly> baseline;
    if (!avx2) baseline.emplace();
    for (int q = 0; q < 144; ++q) {  // the NaN's place: every one, the last four lanes too
      const int p = (q * 7 + 3) % 144;  // the outstanding value's, another
      CAPTURE(p);
      CAPTURE(q);
      KeptTetHessians kept;
      kept.prepare(1, 144, 1.0);
      kept.allocate_blocks();
      std::array<double, 144> first, second, third;
      first.fill(0.5);
      first[p] = -3e4;  // largest held: 3e4, a NaN beside it
      first[q] = std::nan("");
      second.fill(1.0);
      second[q] = std::nan("");
      CHECK_FALSE(kept.replace(0, Mat3::Identity(), first, scatter.data()));
      CHECK(kept.replace(0, Mat3::Identity(), second, scatter.data()));  // 3e4 > 1e4 * 1
      third.fill(-1.0);
      third[p] = -5.0;  // largest new: 5, and held (second) at most 1 apart from its NaN
      CHECK_FALSE(kept.replace(0, Mat3::Identity(), third, scatter.data()));
      kept.replace(0, Mat3::Identity(), first, scatter.data());
      CHECK_FALSE(kept.replace(0, Mat3::Identity(), third, scatter.data()));  // 3e4 < 1e4 * 5
    }
  }
}
