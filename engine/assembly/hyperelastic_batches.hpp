#pragma once
// The hyperelastic elements of a model in the element schedule's order (colours in turn, a
// colour's blocks in parallel, each block's elements in index order), a block's elements
// four at a time: where the projected Hessians are wanted, the SVDs of the one-point tets'
// F (invariant materials: the projection needs F's eigensystem) in one batch
// (compute_rotation_variant_svds: the bits of one at a time, four lanes on AVX2). Each
// element is then visited with its nodes, its quadrature and that F with its SVD, or null.
#include <algorithm>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/for_each_scheduled_element.hpp"
#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/math/rotation_variant_svd.hpp"
#include "engine/model.hpp"

namespace sinew {

inline bool is_hyperelastic_element(const Model& model, int e) {
  return model.bodies[model.element_body[e]].hyperelastic != nullptr;
}

// A one-point tet of an invariant material: its projected Hessian's SVD goes in the batches,
// and its Hessian may be kept (kept_tet_hessians.hpp).
inline bool is_one_point_invariant_tet(const Model& model, int e, int node_count, const ElementQuadrature& quad) {
  return node_count == 4 && !quad.mean_dilatation && quad.points == 1 &&
         model.bodies[model.element_body[e]].hyperelastic->as_invariant();
}

// Every such tet's projected Hessian is wanted (hyperelastic_derivatives without kept Hessians).
struct EveryHessianWanted {
  bool operator()(int, const Mat3&) const { return true; }
};

// visit(e, nodes, quad, given): given holds F = deformation_gradient(quad.dN_dX[0], nodes) and
// its SVD for a one-point tet of an invariant material when `projected_hessians` (F alone,
// svd null, where wanted(e, F) is false: that tet keeps an earlier Hessian,
// kept_tet_hessians.hpp, and needs no SVD), else null. `shared_writes` false: the visits write per-element results only, and the
// schedule's blocks run all at once instead of colour by colour.
struct EveryElementIncluded {
  bool operator()(int) const { return true; }
};

// included(e): whether hyperelastic element e is visited at all (the kept pass leaves out the
// tets whose Hessian it kept, hyperelastic_derivatives.cpp).
template <class Visit, class Wanted = EveryHessianWanted, class Included = EveryElementIncluded>
void for_each_hyperelastic_element(const Model& model, const VecX& x, bool projected_hessians, const Visit& visit,
                                   bool shared_writes = true, const Wanted& wanted = {},
                                   const Included& included = {}) {
  const auto takes = [&](int e) { return is_hyperelastic_element(model, e) && included(e); };
  const auto visit_block = [&](int first, int last) {
    for (int group = first; group < last; group += 4) {
      const int count = std::min(4, last - group);
      ElementNodes nodes[4];
      ElementQuadrature quads[4];
      Mat3 F[4], own_F[4];  // the batch's (contiguous), and the tets' whose Hessian is kept
      RotationVariantSvd svds[4];
      int batched[4], in_batch = 0;
      enum : char { kNone, kBatched, kKept } given_kind[4];
      for (int k = 0; k < count; ++k) {
        const int e = group + k;
        given_kind[k] = kNone;
        if (!takes(e)) continue;
        nodes[k] = gather_element_positions(model, x, e);
        quads[k] = element_quadrature(model, e);
        if (projected_hessians && is_one_point_invariant_tet(model, e, nodes[k].count, quads[k])) {
          own_F[k] = deformation_gradient(quads[k].dN_dX[0], nodes[k]);
          if (wanted(e, own_F[k])) {
            F[in_batch] = own_F[k];
            batched[k] = in_batch++;
            given_kind[k] = kBatched;
          } else {
            given_kind[k] = kKept;
          }
        }
      }
      compute_rotation_variant_svds(F, svds, in_batch);
      for (int k = 0; k < count; ++k) {
        if (!takes(group + k)) continue;
        if (given_kind[k] == kNone) {
          visit(group + k, nodes[k], quads[k], nullptr);
        } else if (given_kind[k] == kKept) {
          const GivenDeformation given{own_F[k], nullptr};
          visit(group + k, nodes[k], quads[k], &given);
        } else {
          const GivenDeformation given{F[batched[k]], &svds[batched[k]]};
          visit(group + k, nodes[k], quads[k], &given);
        }
      }
    }
  };
  if (shared_writes) for_each_scheduled_block(model.element_schedule, visit_block);
  else for_each_scheduled_block_at_once(model.element_schedule, visit_block);
}

}  // namespace sinew
