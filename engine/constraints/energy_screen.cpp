#include "engine/constraints/energy_screen.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "engine/assembly/element_kernels.hpp"
#include "engine/fem/hex8.hpp"

namespace sinew {

namespace {

// sigma_min(F) >= 2 det(F) / |F|_F^2; 0 when det(F) <= 0 (no bound: the rotation of an
// inverted F is not its orthogonal polar factor).
double sigma_min_bound(const Mat3& F) {
  const double det = F.determinant(), norm2 = F.squaredNorm();
  return det > 0 && norm2 > 0 ? 2 * det / norm2 : 0.0;
}

void node_offsets(const std::array<Vec3, 8>& x, std::array<Vec3, 8>& offsets) {
  for (int n = 0; n < 8; ++n) offsets[n] = x[n] - x[0];
}

}  // namespace

void record_energy_reference(const Model& model, const VecX& x, const std::vector<double>& ratio,
                             EnergyScreen& screen) {
  if (screen.model != &model) {
    screen.root_lambda.assign(model.references.size(), 0.0);
    for (size_t r = 0; r < model.references.size(); ++r) {
      const Eigen::SelfAdjointEigenSolver<Mat24> eigen(model.references[r].Ke, Eigen::EigenvaluesOnly);
      screen.root_lambda[r] = std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
    }
    screen.model = &model;
  }
  const int count = model.num_elements;
  screen.x_ref = x;
  screen.root.assign(count, -1.0);
  screen.F_ref.resize(count);
  screen.sigma_ref.assign(count, 0.0);
  screen.spread.assign(count, 0.0);
  for (int e = 0; e < count; ++e) {
    if (model.element_Umax[e] <= 0 || model.element_type[e] != ElementType::Hex8) continue;
    const ElementNodes nodes = gather_element_nodes(model, x, e);
    const double cell = model.references[model.element_reference[e]].cell_size;
    screen.F_ref[e] = hex8_inner_deformation_gradient(nodes.x, cell);
    screen.sigma_ref[e] = sigma_min_bound(screen.F_ref[e]);
    if (screen.sigma_ref[e] <= 0) continue;
    std::array<Vec3, 8> offsets;
    node_offsets(nodes.x, offsets);
    double spread2 = 0;
    for (const Vec3& o : offsets) spread2 += o.squaredNorm();
    screen.spread[e] = std::sqrt(spread2);
    screen.root[e] = std::sqrt(std::max(0.0, ratio[e] * model.element_Umax[e]));
  }
  screen.valid = true;
}

double energy_ratio_bound(const Model& model, const EnergyScreen& screen, const VecX& x, int e) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!screen.valid || screen.root[e] < 0) return kNone;
  const ElementNodes now = gather_element_nodes(model, x, e), then = gather_element_nodes(model, screen.x_ref, e);
  const double cell = model.references[model.element_reference[e]].cell_size;
  const Mat3 F = hex8_inner_deformation_gradient(now.x, cell);
  const double sigma = sigma_min_bound(F);
  if (sigma <= 0) return kNone;
  const double rotation_change = 2 * (F - screen.F_ref[e]).norm() / (sigma + screen.sigma_ref[e]);
  std::array<Vec3, 8> offsets, offsets_ref;
  node_offsets(now.x, offsets);
  node_offsets(then.x, offsets_ref);
  double moved2 = 0;
  for (int n = 0; n < 8; ++n) moved2 += (offsets[n] - offsets_ref[n]).squaredNorm();
  const double root = screen.root[e] + screen.root_lambda[model.element_reference[e]] *
                                           (std::sqrt(moved2) + rotation_change * screen.spread[e]);
  // Inflated past the round-off of both this bound and the exact evaluation it stands for.
  return (1 + 1e-6) * root * root / model.element_Umax[e] + 1e-12;
}

}  // namespace sinew
