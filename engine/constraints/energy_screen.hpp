#pragma once
// Leaves hex elements far below their energy limit out of a row build without computing
// their rotation and energy, by a bound that holds, so the rows built are the same. Each
// SQP iteration of a step evaluates every limited element at its iterate (a polar
// decomposition and a 24 x 24 product each); the iterates, and the steps of a body near
// rest, move little.
//
// With R the element's rotation (the polar factor of its inner tetrahedron's F, hex8.hpp),
// u = R^T x - X and Ue = u^T Ke u, against a reference evaluation at x_ref:
//   sqrt(Ue(x)) <= sqrt(Ue(x_ref)) + sqrt(lambda_max(Ke)) (|dx~| + |R - R_ref|_F |x~_ref|)
// where x~ are node positions relative to node 0 (Ke annihilates translations) and dx~ their
// change; and, for F and F_ref with positive determinants (Li 1995, the unitary polar factor),
//   |R - R_ref|_F <= 2 |F - F_ref|_F / (sigma_min(F) + sigma_min(F_ref)),
//   sigma_min(F) >= 2 det(F) / |F|_F^2     (sigma_1 sigma_2 <= |F|_F^2 / 2),
// taken only where det(F) > 1e-2 |F|_F^3 / (3 sqrt 3) at both points (10x above the
// polar code's own switch to its SVD: the rotation is then F's orthogonal polar factor).
// The computed exact value carries round-off that grows with the nodes' distance from the
// origin (u = R^T x - X holds their rigid translation, which Ke annihilates only to
// round-off): the bound adds 1024 eps lambda_max (|x| + |X|)^2 / Umax for it.
//
// The bound holds for any x and any reference, whenever it was taken: each element keeps its
// own, from its last exact evaluation, across SQP iterations and steps (an element whose
// bound rises above the threshold is evaluated, and its reference moves there). Ke and the
// rest shape never change; sqrt(Ue) is kept rather than Ue / Umax, which a sleeping body's
// frozen model (Umax 0) would not share.
#include <array>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/model.hpp"

namespace sinew {

struct EnergyScreen {
  bool valid = false;             // sized for the model, and every element's entry meaningful
  // Per element, at its reference: sqrt(Ue) (< 0: none: never evaluated, a tet, or inverted
  // there), the inner tetrahedron's F, |x~_ref| over the 8 nodes, |x_ref| over them, x~_ref.
  std::vector<double> root;
  std::vector<Mat3> F_ref;
  std::vector<double> spread;
  std::vector<double> reach;
  std::vector<std::array<Vec3, 8>> offsets;
  long screened = 0;              // elements left out by the last build (tests)
};

// Li's bound on |polar(F) - polar(F_ref)|_F with the sigma_min bounds above; +infinity
// unless both are well away from singular (the condition above).
double polar_change_bound(const Mat3& F, const Mat3& F_ref);

// Sizes the screen for the model (every element without a reference); no allocation when it
// already is.
void prepare_energy_screen(const Model& model, EnergyScreen& screen);
// Records element e's exact ratio (Ue / Umax, as energy_limit.cpp computes it) at x as its
// reference; elements apart may be recorded in parallel.
void record_element_reference(const Model& model, const VecX& x, int e, double ratio, EnergyScreen& screen);
// The same for every limited element.
void record_energy_reference(const Model& model, const VecX& x, const std::vector<double>& ratio,
                             EnergyScreen& screen);
// An upper bound of Ue(x) / Umax for element e, or +infinity when the bound does not apply.
double energy_ratio_bound(const Model& model, const EnergyScreen& screen, const VecX& x, int e);

}  // namespace sinew
