#include "engine/constraints/energy_screen.hpp"

#include <cmath>
#include <limits>

#include "engine/assembly/element_kernels.hpp"
#include "engine/fem/hex8.hpp"

namespace sinew {

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// sigma_min(F) >= 2 det(F) / |F|_F^2; 0 unless det(F) > 1e-2 |F|_F^3 / (3 sqrt 3).
double sigma_min_bound(const Mat3& F) {
  const double det = F.determinant(), norm2 = F.squaredNorm();
  return det > 1e-2 * norm2 * std::sqrt(norm2) / (3 * std::sqrt(3.0)) ? 2 * det / norm2 : 0.0;
}

void node_offsets(const std::array<Vec3, 8>& x, std::array<Vec3, 8>& offsets) {
  for (int n = 0; n < 8; ++n) offsets[n] = x[n] - x[0];
}

double norm_of(const std::array<Vec3, 8>& x) {
  double sum = 0;
  for (const Vec3& p : x) sum += p.squaredNorm();
  return std::sqrt(sum);
}

}  // namespace

double polar_change_bound(const Mat3& F, const Mat3& F_ref) {
  const double sigma = sigma_min_bound(F), sigma_ref = sigma_min_bound(F_ref);
  if (sigma <= 0 || sigma_ref <= 0) return kNone;
  return 2 * (F - F_ref).norm() / (sigma + sigma_ref);
}

void prepare_energy_screen(const Model& model, EnergyScreen& screen) {
  const std::size_t count = model.num_elements;
  if (screen.valid && screen.root.size() == count) return;
  screen.root.assign(count, -1.0);
  screen.F_ref.resize(count);
  screen.spread.assign(count, 0.0);
  screen.reach.assign(count, 0.0);
  screen.offsets.resize(count);
  screen.valid = true;
}

void record_element_reference(const Model& model, const VecX& x, int e, double ratio, EnergyScreen& screen) {
  screen.root[e] = -1.0;
  if (model.element_Umax[e] <= 0 || model.element_type[e] != ElementType::Hex8 || !std::isfinite(ratio)) return;
  const ElementNodes nodes = gather_element_nodes(model, x, e);
  const double cell = model.references[model.element_reference[e]].cell_size;
  screen.F_ref[e] = hex8_inner_deformation_gradient(nodes.x, cell);
  if (sigma_min_bound(screen.F_ref[e]) <= 0) return;
  std::array<Vec3, 8>& offsets = screen.offsets[e];
  node_offsets(nodes.x, offsets);
  double spread2 = 0;
  for (const Vec3& o : offsets) spread2 += o.squaredNorm();
  screen.spread[e] = std::sqrt(spread2);
  screen.reach[e] = norm_of(nodes.x);
  screen.root[e] = std::sqrt(std::max(0.0, ratio * model.element_Umax[e]));
}

void record_energy_reference(const Model& model, const VecX& x, const std::vector<double>& ratio,
                             EnergyScreen& screen) {
  prepare_energy_screen(model, screen);
  for (int e = 0; e < model.num_elements; ++e) record_element_reference(model, x, e, ratio[e], screen);
}

double energy_ratio_bound(const Model& model, const EnergyScreen& screen, const VecX& x, int e) {
  if (!screen.valid || screen.root[e] < 0 || model.element_Umax[e] <= 0) return kNone;
  const ElementNodes now = gather_element_nodes(model, x, e);
  const Hex8Reference& ref = model.references[model.element_reference[e]];
  const Mat3 F = hex8_inner_deformation_gradient(now.x, ref.cell_size);
  const double rotation_change = polar_change_bound(F, screen.F_ref[e]);
  if (rotation_change == kNone) return kNone;
  std::array<Vec3, 8> offsets;
  node_offsets(now.x, offsets);
  const std::array<Vec3, 8>& offsets_ref = screen.offsets[e];
  double moved2 = 0;
  for (int n = 0; n < 8; ++n) moved2 += (offsets[n] - offsets_ref[n]).squaredNorm();
  const double root =
      screen.root[e] + ref.root_lambda_max * (std::sqrt(moved2) + rotation_change * screen.spread[e]);
  const double reach = std::max(norm_of(now.x), screen.reach[e]) + norm_of(now.X);
  const double round_off = 1024 * std::numeric_limits<double>::epsilon() * ref.root_lambda_max *
                           ref.root_lambda_max * reach * reach;
  return ((1 + 1e-6) * root * root + round_off) / model.element_Umax[e];
}

}  // namespace sinew
