// Strain rows with deferred Jacobians (strain_limit_rows.hpp): the SQP's line-search trials
// build their rows without Jacobians and complete them only where a QP is linearised. The
// completed table must be the immediate build's, bit for bit, wherever other rows follow.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <random>

#include "engine/constraints/strain_limit_rows.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// A bar stretched by a pull along x against a 5 % limit, then its nodes scattered by up to
// 1 % of a cell: some rows carry force (kept), some tets sit near their limits, some past.
std::unique_ptr<World> stretched_bar() {
  const SceneDesc scene = parse_scene_text(R"({"h": 0.02, "gravity": [0, 0, 0],
    "bodies": [{"name": "bar", "shape": [{"type": "box", "half_extents": [0.3, 0.05, 0.05]}],
      "cell_size": 0.05, "elements": "tet",
      "material": {"E": 5e3, "nu": 0.3, "rho": 500}, "damping": {"mass": 2},
      "fixed": [{"half_space": {"point": [-0.29, 0, 0], "normal": [1, 0, 0]}}],
      "loads": [{"half_space": {"point": [0.29, 0, 0], "normal": [-1, 0, 0]}, "force": [20, 0, 0], "ramp_time": 0.3}],
      "strain_limit": {"mode": "hyperbolic", "smin": [0.95, 0.9, 0.9], "smax": [1.05, 1.1, 1.1]}}]})",
                                           "frames", ".");
  auto world = std::make_unique<World>(build_model(scene, [](const std::string&) {}));
  for (int i = 0; i < 30; ++i) REQUIRE(world->step());
  return world;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("strain rows: deferred Jacobians, completed, equal the immediate build bit for bit") {
  const std::unique_ptr<World> bar = stretched_bar();
  const World& world = *bar;
  const Model& model = world.model();
  VecX x = world.state().x;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-5e-4, 5e-4);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += jitter(rng);
  std::vector<uint64_t> keep;
  for (const auto& [key, lambda] : world.state().warm_start)
    if (lambda > 0 && row_key_kind(key) == RowKind::Strain) keep.push_back(key);
  std::sort(keep.begin(), keep.end());
  REQUIRE(!keep.empty());
  const double margin = model.solver.strain_activation_margin;

  RowTable now;
  const double worst_now = add_strain_limit_rows(model, x, margin, keep, now);
  REQUIRE(now.size() > 0);

  KeptStorage<StrainRowBuffers> storage;
  RowTable deferred;
  deferred.add_row(RowKind::Contact, 0.25, 0, 1e300, 1);  // a row before the strain rows
  deferred.add_entry(0, Vec3(1, 2, 3));
  const double worst_deferred =
      add_strain_limit_rows(model, x, margin, keep, deferred, &storage, StrainJacobians::Deferred);
  CHECK(same_bits(worst_now, worst_deferred));
  REQUIRE(deferred.size() == now.size() + 1);
  for (int k = deferred.begin[1]; k < deferred.begin[deferred.size()]; ++k) REQUIRE(deferred.jac[k] == Vec3::Zero());
  deferred.add_row(RowKind::Contact, 0.5, 0, 1e300, 2);  // and one after them
  deferred.add_entry(1, Vec3(4, 5, 6));

  complete_strain_limit_jacobians(model, deferred, &storage);
  int differing = 0;
  for (int i = 0; i < now.size(); ++i) {
    const int j = i + 1;
    REQUIRE(deferred.key[j] == now.key[i]);
    REQUIRE(same_bits(deferred.value[j], now.value[i]));
    REQUIRE(deferred.element[j] == now.element[i]);
    REQUIRE(deferred.begin[j + 1] - deferred.begin[j] == now.begin[i + 1] - now.begin[i]);
    for (int a = 0; a < now.begin[i + 1] - now.begin[i]; ++a) {
      REQUIRE(deferred.nodes[deferred.begin[j] + a] == now.nodes[now.begin[i] + a]);
      for (int c = 0; c < 3; ++c)
        differing += !same_bits(deferred.jac[deferred.begin[j] + a][c], now.jac[now.begin[i] + a][c]);
    }
  }
  CHECK(differing == 0);
  // The rows around them are untouched.
  CHECK(deferred.jac[0] == Vec3(1, 2, 3));
  CHECK(deferred.jac.back() == Vec3(4, 5, 6));

  // Completed once: a second call changes nothing (the first strain row's Jacobian zeroed
  // by hand stays zero).
  deferred.jac[deferred.begin[1]] = Vec3::Zero();
  complete_strain_limit_jacobians(model, deferred, &storage);
  CHECK(deferred.jac[deferred.begin[1]] == Vec3::Zero());
}

TEST_CASE("strain rows: pair cuts gated by the step's start velocities, deferred or not") {
  // strain_limit_rows.hpp: a pair gets its cuts where gap < 4 delta^2 / tolerance, delta = h
  // |L| for the velocity gradient L. Every constraint is asked for (margin +inf),
  // so without a gate every pair within kStrainLimitBlendGap has its cuts.
  const std::unique_ptr<World> bar = stretched_bar();
  const Model& model = bar->model();
  const VecX& x = bar->state().x;
  const double all = std::numeric_limits<double>::infinity();
  const auto cuts_in = [](const RowTable& rows) {
    int n = 0;
    for (int i = 0; i < rows.size(); ++i) n += row_key_second(rows.key[i]) >= kStrainCutFirst;
    return n;
  };
  // Start velocities on the free nodes from a velocity gradient L: v = L (x - c).
  const auto flow = [&](const Mat3& L) {
    VecX v = VecX::Zero(3 * model.num_free);
    for (int n = 0; n < model.num_nodes; ++n)
      if (const int f = model.free_index[n]; f >= 0) v.segment<3>(3 * f) = L * x.segment<3>(3 * n);
    return v;
  };
  Mat3 shear = Mat3::Zero(), slow = Mat3::Zero();
  shear(0, 1) = shear(1, 0) = 1.0;  // 1/s: 4 (h sqrt2)^2 / 1e-3 = 3.2, far above the blend gap
  slow(0, 1) = slow(1, 0) = 1e-3;   // 4 (h sqrt2 1e-3)^2 / 1e-3 = 3.2e-6: only pairs that close
  RowTable ungated, still, sheared, crept;
  add_strain_limit_rows(model, x, all, {}, ungated);
  KeptStorage<StrainRowBuffers> storage;
  std::vector<double> gaps_still, gaps_shear, gaps_slow;
  strain_pair_cut_gaps(model, flow(Mat3::Zero()), gaps_still);
  strain_pair_cut_gaps(model, flow(shear), gaps_shear);
  strain_pair_cut_gaps(model, flow(slow), gaps_slow);
  REQUIRE(gaps_still.size() == static_cast<size_t>(model.num_elements));
  add_strain_limit_rows(model, x, all, {}, still, &storage, StrainJacobians::Now, &gaps_still);
  add_strain_limit_rows(model, x, all, {}, sheared, &storage, StrainJacobians::Now, &gaps_shear);
  add_strain_limit_rows(model, x, all, {}, crept, &storage, StrainJacobians::Now, &gaps_slow);
  MESSAGE("cut rows: ungated " << cuts_in(ungated) << ", still " << cuts_in(still) << ", sheared "
                               << cuts_in(sheared) << ", sheared 1000 times slower " << cuts_in(crept));
  REQUIRE(cuts_in(ungated) > 0);
  CHECK(cuts_in(still) == 0);
  CHECK(still.size() == ungated.size() - cuts_in(ungated));  // the paper's rows are all there
  CHECK(cuts_in(sheared) == cuts_in(ungated));
  CHECK(cuts_in(crept) < cuts_in(sheared) / 10);  // only pairs within 3.2e-6 of each other

  // Deferred and completed with the same gate: the immediate table, bit for bit.
  RowTable deferred;
  add_strain_limit_rows(model, x, all, {}, deferred, &storage, StrainJacobians::Deferred, &gaps_shear);
  complete_strain_limit_jacobians(model, deferred, &storage);
  REQUIRE(deferred.size() == sheared.size());
  int differing = 0;
  for (int i = 0; i < sheared.size(); ++i) {
    REQUIRE(deferred.key[i] == sheared.key[i]);
    differing += !same_bits(deferred.value[i], sheared.value[i]);
    for (int k = sheared.begin[i]; k < sheared.begin[i + 1]; ++k)
      for (int c = 0; c < 3; ++c) differing += !same_bits(deferred.jac[k][c], sheared.jac[k][c]);
  }
  CHECK(differing == 0);
}
