#include "engine/step/hyperelastic_derivatives.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/assembly/hyperelastic_batches.hpp"
#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/assembly/node_elements.hpp"
#include "engine/assembly/kept_tet_hessians.hpp"
#include "engine/assembly/scatter_stiffness.hpp"

namespace sinew {

namespace {

// kept->fresh per element in a pass: its Hessian scattered straight into the values (not a
// one-point invariant tet), formed afresh into its kept blocks (after larger ones: the kept
// sum is summed anew after the pass, KeptTetHessians::replace), or kept.
enum KeptPass : char { kDirect = 0, kFresh = 1, kFreshAfterLarger = 2, kKept = 3 };

// A tet's projected Hessian formed afresh into its kept blocks, and kept->values changed by
// the difference from the blocks it held (none: zeros). Its energy; its gradient into g.
double form_kept_tet_hessian(const Model& model, int e, const Material& material, const ElementQuadrature& quad,
                             const ElementNodes& nodes, const GivenDeformation& given, Vec12& g,
                             KeptTetHessians& kept) {
  // The blocks go to a 144-value buffer laid out as the 48 block columns of three values (a
  // fixed node's blocks skipped, as in the system's values).
  const int* at = model.pattern.element_scatter.data() + model.pattern.scatter_begin[e];
  int positions[48];
  for (int i = 0; i < 48; ++i) positions[i] = at[i] < 0 ? -1 : 3 * i;
  alignas(32) std::array<double, 144> formed{};
  const TetHessianScatter local{positions, kept.coeff, formed.data()};
  const double energy = hyperelastic_tet_derivatives(material, quad, nodes, g, local, &given);
  if (kept.replace(e, given.F, formed, at)) kept.fresh[e] = kFreshAfterLarger;
  return energy;
}

// Fills kept.every_element_kept and kept.any_element_kept (once per model and pattern).
void classify_kept_elements(const Model& model, KeptTetHessians& kept) {
  kept.prepare(model.num_elements, static_cast<int>(model.pattern.matrix.nonZeros()), model.h * model.h);
  if (kept.every_element_kept >= 0) return;
  bool every = true, any = false;
  for (int e = 0; e < model.num_elements; ++e) {
    if (!is_hyperelastic_element(model, e)) continue;
    const bool keeps = one_point_invariant_tet(model, e) != nullptr;
    every = every && keeps;
    any = any || keeps;
  }
  kept.every_element_kept = every ? 1 : 0;
  kept.any_element_kept = any ? 1 : 0;
  if (any) kept.allocate_blocks();
}

}  // namespace

bool keeps_every_hessian(const Model& model, KeptTetHessians& kept) {
  classify_kept_elements(model, kept);
  return kept.every_element_kept == 1;
}

bool keeps_any_hessian(const Model& model, KeptTetHessians& kept) {
  classify_kept_elements(model, kept);
  return kept.any_element_kept == 1;
}

void hyperelastic_derivatives(const Model& model, const VecX& x, bool exact, std::vector<double>& energy,
                              std::vector<double>& force2, VecX& gradient, double* values,
                              std::vector<Vec3>& node_gradients, KeptTetHessians* kept,
                              double reuse_tolerance, bool overwrite) {
  // Kept Hessians only for the projected ones (the exact Hessian of Newton's last iterations
  // is formed whole).
  if (!values || exact) kept = nullptr;
  if (kept && !keeps_any_hessian(model, *kept)) kept = nullptr;  // no element could use it
  if (kept) {
    if (!keeps_every_hessian(model, *kept) && overwrite)
      throw std::logic_error("hyperelastic_derivatives: overwriting values where some Hessians are not kept");
    std::fill(kept->fresh.begin(), kept->fresh.end(), kDirect);
  } else if (overwrite) {
    throw std::logic_error("hyperelastic_derivatives: overwriting values without kept Hessians");
  }
  energy.assign(model.num_elements, 0.0);
  force2.assign(model.num_elements, 0.0);
  const NodeElements& incidence = model.node_elements;
  node_gradients.resize(incidence.entries.size());
  // g over the element's `count` nodes, each node's part at its entry of the incidence.
  const auto keep_gradient = [&](int e, int count, const auto& g) {
    force2[e] = g.squaredNorm();
    const std::array<int, 8>& slot = incidence.slot[e];
    for (int a = 0; a < count; ++a) node_gradients[slot[a]] = g.template segment<3>(3 * a);
  };
  // given: F and its SVD, for a tet whose projected Hessian is wanted (from the batch below), or null.
  const auto visit = [&](int e, const ElementNodes& nodes, const ElementQuadrature& quad,
                         const GivenDeformation* given) {
    const Material& material = *model.bodies[model.element_body[e]].hyperelastic;
    // Tets: the exact Hessian (Newton near convergence) in 12 x 12 and scattered, the projected
    // one added straight into the values.
    if (nodes.count == 4 && !quad.mean_dilatation) {
      Vec12 g;
      const char pass = kept ? kept->fresh[e] : static_cast<char>(kDirect);
      if (pass == kFresh) {
        energy[e] = form_kept_tet_hessian(model, e, material, quad, nodes, *given, g, *kept);
      } else if (values && exact) {
        Mat12 K;
        energy[e] = hyperelastic_tet_exact_derivatives(material, quad, nodes, g, K);
        scatter_element_matrix(model, e, K, model.h * model.h, values);
      } else if (values) {  // projected: added straight into the values (tet_hessian_scatter.hpp)
        const TetHessianScatter scatter{model.pattern.element_scatter.data() + model.pattern.scatter_begin[e],
                                        model.h * model.h, values};
        energy[e] = hyperelastic_tet_derivatives(material, quad, nodes, g, scatter, given);
      } else {
        energy[e] = hyperelastic_tet_derivatives(material, quad, nodes, g, nullptr, given);
      }
      keep_gradient(e, 4, g);
      return;
    }
    Vec24 g;
    Mat24 K;
    energy[e] = values && exact ? hyperelastic_element_exact_derivatives(material, quad, nodes, g, K)
                                : hyperelastic_element_derivatives(material, quad, nodes, g, values ? &K : nullptr);
    keep_gradient(e, nodes.count, g);
    if (values) scatter_element_matrix(model, e, K, model.h * model.h, values);
  };
  // A one-point tet of an invariant material, its F from x: the energies-and-gradient path
  // (no gathered copy of its nodes, no quadrature or batch bookkeeping; the same bits).
  const auto lean_energy_gradient = [&](int e, const InvariantMaterial& material, const Mat3& F) {
    const int reference = model.element_reference[e];
    Vec12 g;
    energy[e] = invariant_tet_energy_gradient(material, F, model.tet_gradients[reference], model.tet_volumes[reference], g);
    keep_gradient(e, 4, g);
  };
  const auto tet_F = [&](int e) {
    return tet_deformation_gradient(model.tet_gradients[model.element_reference[e]], x, model.element_nodes[e]);
  };
  // The projected tet Hessians' SVDs four at a time (hyperelastic_batches.hpp).
  if (kept) {
    // First every element at once (its results are its own): which tets keep their Hessian
    // (F moved by at most the tolerance), and those tets' energy and gradient. Then, through
    // the schedule (colour by colour: forming a Hessian changes the shared kept sum), only the
    // rest: a resting body's pass is the gradient pass and a comparison of F per tet, with no
    // colour barrier (cube_20 at rest: 13,200 tets kept, none formed).
    std::atomic<bool> any_left{false};
    tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 256), [&](const tbb::blocked_range<int>& range) {
      bool left = false;
      for (int e = range.begin(); e < range.end(); ++e) {
        if (!is_hyperelastic_element(model, e)) continue;
        const InvariantMaterial* material = one_point_invariant_tet(model, e);
        if (!material) {
          left = true;
          continue;
        }
        const Mat3 F = tet_F(e);
        if (kept->needs_forming(e, F, reuse_tolerance)) {
          kept->fresh[e] = kFresh;
          left = true;
          continue;
        }
        kept->fresh[e] = kKept;
        lean_energy_gradient(e, *material, F);
      }
      if (left) any_left.store(true, std::memory_order_relaxed);
    });
    // The batch's F is tet_F's (the same sums): a tet marked fresh above is formed there.
    const auto left_over = [&](int e) { return kept->fresh[e] != kKept; };
    if (any_left.load()) for_each_hyperelastic_element(model, x, true, visit, left_over);
    long formed = 0;
    bool after_larger = false;
    for (char pass : kept->fresh) {
      formed += pass == kFresh || pass == kFreshAfterLarger;
      after_larger = after_larger || pass == kFreshAfterLarger;
    }
    kept->formed = formed;
    if (after_larger) kept->rebuild(model.pattern.element_scatter, model.pattern.scatter_begin);
    // The kept blocks' sum joins the elements scattered directly (entry by entry: the same
    // bits for any thread count).
    const int entries = kept->entries;
    tbb::parallel_for(tbb::blocked_range<int>(0, entries, 16384), [&](const tbb::blocked_range<int>& r) {
      if (overwrite) std::copy(kept->values.begin() + r.begin(), kept->values.begin() + r.end(), values + r.begin());
      else
        for (int i = r.begin(); i < r.end(); ++i) values[i] += kept->values[i];
    });
  } else if (!values) {
    // Energies and gradient alone: every element's results are its own, so the elements run
    // in any order, and a one-point tet of an invariant material takes its F from x and
    // invariant_tet_energy_gradient (no gathered copy of its nodes, no quadrature or batch
    // bookkeeping: the same bits; cube_20's pass, one thread, 1.78 -> 1.25 ms).
    tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 256), [&](const tbb::blocked_range<int>& range) {
      for (int e = range.begin(); e < range.end(); ++e) {
        if (!is_hyperelastic_element(model, e)) continue;
        if (const InvariantMaterial* material = one_point_invariant_tet(model, e)) {
          lean_energy_gradient(e, *material, tet_F(e));
        } else {
          visit(e, gather_element_positions(model, x, e), element_quadrature(model, e), nullptr);
        }
      }
    });
  } else {
    for_each_hyperelastic_element(model, x, !exact, visit);
  }
  // A free node's elements are all of its body, hyperelastic or not alike, and awake.
  gradient.resize(3 * model.num_free);
  sum_by_node(incidence, [&](int n, int first, int last) {
    const int f = model.free_index[n];
    if (f < 0) return;
    Vec3 sum = Vec3::Zero();
    if (first < last && is_hyperelastic_element(model, incidence.entries[first].first))
      for (int k = first; k < last; ++k) sum += node_gradients[k];
    gradient.segment<3>(3 * f) = sum;
  });
}

}  // namespace sinew
