// The energies-only pass (the trials of Newton's last iteration) against the energies of the
// full pass: the same bits, so that the line search decides as it would with the gradient.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/step/hyperelastic_derivatives.hpp"
#include "tests/support/mixed_hyperelastic_model.hpp"

using namespace sinew;

namespace {

// Mean-dilatation hexes of Stable Neo-Hookean: the one path the mixed model lacks.
Model mean_dilatation_model() {
  const char* text = R"({"h": 0.01, "gravity": [0, 0, 0], "bodies": [
    {"name": "md", "shape": [{"type": "box", "half_extents": [0.1, 0.05, 0.05]}], "cell_size": 0.05,
     "elements": "hex", "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 1000,
     "volume_term": "mean_dilatation"}}]})";
  return build_model(parse_scene_text(text, "mean_dilatation", "."), [](const std::string&) {});
}

// Energies from both passes at x, compared entry by entry (+infinity included).
void check_same_energies(const Model& model, const VecX& x) {
  std::vector<double> full, force2, alone;
  std::vector<Vec24> element_gradients;
  VecX gradient;
  hyperelastic_derivatives(model, x, false, full, force2, gradient, nullptr, element_gradients);
  hyperelastic_energies(model, x, alone);
  REQUIRE(alone.size() == full.size());
  int differing = 0;
  for (size_t e = 0; e < full.size(); ++e) differing += !(alone[e] == full[e]);
  CHECK(differing == 0);
}

}  // namespace

TEST_CASE("hyperelastic energies alone: the full pass's bits on every element kind, inverted ones included") {
  struct Case {
    Model model;
    bool neo_hookean;  // has neo-Hookean elements (undefined energy once inverted)
  };
  for (const Case& c : {Case{test::mixed_hyperelastic_model(), true}, Case{mean_dilatation_model(), false}}) {
    const Model& model = c.model;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    VecX x = model.rest_x;
    check_same_energies(model, x);  // at rest: zeros
    for (int round = 0; round < 4; ++round) {
      for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = model.rest_x[i] + 0.01 * u(rng);
      check_same_energies(model, x);
    }
    // Collapsed through itself: inverted elements (the neo-Hookean's undefined energy is
    // +infinity in both passes; Stable Neo-Hookean stays finite).
    for (int n = 0; n < model.num_nodes; ++n) x[3 * n] = -model.rest_x[3 * n];
    check_same_energies(model, x);
    std::vector<double> energy;
    hyperelastic_energies(model, x, energy);
    bool any_infinite = false;
    for (double psi : energy) any_infinite = any_infinite || std::isinf(psi);
    CHECK(any_infinite == c.neo_hookean);
  }
}
