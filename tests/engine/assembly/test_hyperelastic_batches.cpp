// for_each_hyperelastic_element (hyperelastic_batches.hpp): every hyperelastic element once,
// in the schedule's order within each block, with F and its SVD exactly where a projected
// one-point tet Hessian of an invariant material needs them, equal bit for bit to ones
// computed alone.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>
#include <random>
#include <vector>

#include "engine/assembly/hyperelastic_batches.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/scene/scene.hpp"
#include "engine/world.hpp"
#include "tests/support/mixed_hyperelastic_model.hpp"

using namespace sinew;

namespace {

bool same_bits(const RotationVariantSvd& a, const RotationVariantSvd& b) {
  return std::memcmp(a.U.data(), b.U.data(), sizeof(double) * 9) == 0 &&
         std::memcmp(a.S.data(), b.S.data(), sizeof(double) * 3) == 0 &&
         std::memcmp(a.V.data(), b.V.data(), sizeof(double) * 9) == 0;
}

}  // namespace

TEST_CASE("hyperelastic batches: every hyperelastic element once, SVDs where needed, the bits of one at a time") {
  const Model model = test::mixed_hyperelastic_model();
  REQUIRE(model.bodies.size() == 4);
  // Deformed: every node moved by up to 1 cm, so that F differs from tet to tet.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  VecX x = model.rest_x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  for (const bool avx2 : {true, false}) {
    CAPTURE(avx2);
    std::optional<BaselineKernelsOnly> baseline;
    if (!avx2) baseline.emplace();
    for (const bool projected : {true, false}) {
      CAPTURE(projected);
      std::vector<int> visits(model.num_elements, 0);
      std::vector<int> batched_tets(4, 0), wrong(4, 0), missing(4, 0);
      std::mutex mutex;
      for_each_hyperelastic_element(model, x, projected, [&](int e, const ElementNodes& nodes,
                                                              const ElementQuadrature& quad,
                                                              const GivenDeformation* given) {
        const std::lock_guard<std::mutex> lock(mutex);
        ++visits[e];
        const int body = model.element_body[e];
        const bool wants = projected && nodes.count == 4 && quad.points == 1;
        if (!wants) {
          if (given) ++wrong[body];
          return;
        }
        if (!given) {
          ++missing[body];
          return;
        }
        ++batched_tets[body];
        const Mat3 F = deformation_gradient(quad.dN_dX[0], nodes);
        if (std::memcmp(given->F.data(), F.data(), sizeof(double) * 9) != 0 ||
            !given->svd || !same_bits(*given->svd, compute_rotation_variant_svd(F)))
          ++wrong[body];
      });
      for (int e = 0; e < model.num_elements; ++e)
        CHECK(visits[e] == (model.bodies[model.element_body[e]].hyperelastic ? 1 : 0));
      CHECK(wrong == std::vector<int>(4, 0));
      CHECK(missing == std::vector<int>(4, 0));
      if (projected) {
        CHECK(batched_tets[0] > 4);  // the tet bodies, several groups each
        CHECK(batched_tets[3] > 4);
      }
      CHECK(batched_tets[1] == 0);
      CHECK(batched_tets[2] == 0);
    }
  }
}

TEST_CASE("hyperelastic batches: each block's elements in index order") {
  const Model model = test::mixed_hyperelastic_model();
  const VecX x = model.rest_x;
  // Per block, the elements visited, in the order visited (one block runs on one thread).
  std::vector<int> order;
  std::mutex mutex;
  std::vector<std::vector<int>> per_block;
  for_each_scheduled_block(model.element_schedule, [&](int first, int last) {
    const std::lock_guard<std::mutex> lock(mutex);
    std::vector<int> expected;
    for (int e = first; e < last; ++e)
      if (model.bodies[model.element_body[e]].hyperelastic) expected.push_back(e);
    per_block.push_back(expected);
  });
  std::vector<int> visited;
  for_each_hyperelastic_element(model, x, true, [&](int e, const ElementNodes&, const ElementQuadrature&,
                                                    const GivenDeformation*) {
    const std::lock_guard<std::mutex> lock(mutex);
    visited.push_back(e);
  });
  // Within each block the visits come in index order, whatever the interleaving of blocks.
  for (const std::vector<int>& block : per_block) {
    if (block.empty()) continue;
    std::vector<int> seen;
    for (const int e : visited)
      if (e >= block.front() && e <= block.back()) seen.push_back(e);
    CHECK(seen == block);
  }
}
