#include "engine/constraints/energy_limit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "engine/analysis/element_fields.hpp"
#include "engine/assembly/element_kernels.hpp"

namespace sinew {

EnergyLimitEval evaluate_energy_limit(const Vec24& Ku, const Mat3& R, const Vec24& u,
                                      double Umax, EnergyJacobian mode) {
  EnergyLimitEval out;
  const double Ue = u.dot(Ku);
  out.ratio = Ue / Umax;
  out.value = 1 - out.ratio;
  const double scale = (mode == EnergyJacobian::Exact ? -2.0 : -1.0) / Umax;
  for (int n = 0; n < 8; ++n) out.jac.segment<3>(3 * n) = scale * (R * Ku.segment<3>(3 * n));
  return out;
}

// add_energy_limit_rows' kept storage (kept_storage.hpp).
struct EnergyRowBuffers {
  std::vector<double> ratio;
  std::vector<char> bounded;
};

namespace {

EnergyJacobian jacobian_mode(const Model& model, int e) {
  return model.bodies[model.element_body[e]].energy_limit.jacobian == "warped" ? EnergyJacobian::Warped
                                                                               : EnergyJacobian::Exact;
}

double exact_ratio(const Model& model, const VecX& x, int e) {
  return element_limit_energy(model, e, element_corotated_displacement(model, x, e)) / model.element_Umax[e];
}

// Ue / Umax per element (0 for elements without a limit), into `buffers`; valid until their
// next use. With a screen, an element
// whose bound is at most `threshold` gets the bound instead (energy_screen.hpp): it makes no
// row either way, and the largest ratio is exact whenever it is above `threshold`. Every
// element evaluated exactly becomes its own reference.
const std::vector<double>& energy_ratios(const Model& model, const VecX& x, EnergyScreen* screen, double threshold,
                                         EnergyRowBuffers& buffers) {
  std::vector<double>& ratio = buffers.ratio;
  std::vector<char>& bounded = buffers.bounded;
  ratio.assign(model.num_elements, 0.0);
  bounded.assign(model.num_elements, 0);
  if (screen) prepare_energy_screen(model, *screen);
  tbb::parallel_for(0, model.num_elements, [&](int e) {
    if (model.element_Umax[e] <= 0) return;
    if (screen) {
      const double bound = energy_ratio_bound(model, *screen, x, e);
      if (bound <= threshold) {
        ratio[e] = bound;
        bounded[e] = 1;
        return;
      }
    }
    ratio[e] = exact_ratio(model, x, e);
    if (screen) record_element_reference(model, x, e, ratio[e], *screen);
  });
  if (screen) screen->screened = std::count(bounded.begin(), bounded.end(), 1);
  return ratio;
}

double worst_of(const Model& model, const std::vector<double>& ratio) {
  double worst = -1;
  for (int e = 0; e < model.num_elements; ++e)
    if (model.element_Umax[e] > 0) worst = std::max(worst, ratio[e] - 1);
  return worst;
}

}  // namespace

double add_energy_limit_rows(const Model& model, const VecX& x, double margin,
                             const std::vector<uint64_t>& keep, RowTable& rows, EnergyScreen* screen,
                             KeptStorage<EnergyRowBuffers>* storage) {
  const std::vector<double>& ratio = energy_ratios(model, x, screen, 1 - margin, kept_or_thread_local(storage));
  for (int e = 0; e < model.num_elements; ++e) {
    if (model.element_Umax[e] <= 0) continue;
    const uint64_t key = row_key(RowKind::Energy, e);
    if (ratio[e] <= 1 - margin && std::find(keep.begin(), keep.end(), key) == keep.end()) continue;
    Mat3 R;
    const Vec24 u = element_corotated_displacement(model, x, e, &R);
    const EnergyLimitEval eval = evaluate_energy_limit(element_stiffness_times(model, e, u), R, u,
                                                       model.element_Umax[e], jacobian_mode(model, e));
    const int row = rows.add_row(RowKind::Energy, eval.value, 0.0, 1e300, key);
    // C = 1 - u^T Ke u / Umax: -d2C/dx2 = (2 / Umax) R Ke R^T (exact), half that for the
    // warped Jacobian, whose constraint is 1 - 1/2 u^T Ke u / Umax up to a constant.
    rows.element[row] = e;
    rows.curvature[row] = (jacobian_mode(model, e) == EnergyJacobian::Exact ? 2.0 : 1.0) / model.element_Umax[e];
    for (int n = 0; n < element_node_count(model, e); ++n)
      rows.add_entry(model.element_nodes[e][n], eval.jac.segment<3>(3 * n));
  }
  return worst_of(model, ratio);
}

double worst_energy_violation(const Model& model, const VecX& x) {
  return worst_of(model, energy_ratios(model, x, nullptr, 0.0, kept_or_thread_local<EnergyRowBuffers>(nullptr)));
}

}  // namespace sinew
