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
#include "engine/materials/invariant_material.hpp"
#include "engine/math/rotation_variant_svd.hpp"
#include "engine/model.hpp"

namespace sinew {

inline bool is_hyperelastic_element(const Model& model, int e) {
  return model.bodies[model.element_body[e]].hyperelastic != nullptr;
}

// A hyperelastic element that is a tet of an invariant material (a tet has one point and no
// mean dilatation: element_quadrature): its projected Hessian's SVD goes in the batches, its
// Hessian may be kept (kept_tet_hessians.hpp), and its energy and gradient alone take
// invariant_tet_energy_gradient. That material, else null.
inline const InvariantMaterial* one_point_invariant_tet(const Model& model, int e) {
  return model.element_type[e] == ElementType::Tet4 ? model.bodies[model.element_body[e]].hyperelastic->as_invariant()
                                                     : nullptr;
}

struct EveryElementIncluded {
  bool operator()(int) const { return true; }
};

// visit(e, nodes, quad, given), colour by colour (a colour's blocks in parallel): given holds
// F = deformation_gradient(quad.dN_dX[0], nodes) and its SVD for a one-point tet of an
// invariant material when `projected_hessians`, else null. included(e): whether hyperelastic
// element e is visited at all (the kept pass leaves out the tets that keep their Hessian,
// hyperelastic_derivatives.cpp, which it takes in a loop of its own).
template <class Visit, class Included = EveryElementIncluded>
void for_each_hyperelastic_element(const Model& model, const VecX& x, bool projected_hessians, const Visit& visit,
                                   const Included& included = {}) {
  const auto takes = [&](int e) { return is_hyperelastic_element(model, e) && included(e); };
  for_each_scheduled_block(model.element_schedule, [&](int first, int last) {
    for (int group = first; group < last; group += 4) {
      const int count = std::min(4, last - group);
      ElementNodes nodes[4];
      ElementQuadrature quads[4];
      Mat3 F[4];  // the batch's, contiguous
      RotationVariantSvd svds[4];
      int batched[4], in_batch = 0;
      for (int k = 0; k < count; ++k) {
        const int e = group + k;
        batched[k] = -1;
        if (!takes(e)) continue;
        nodes[k] = gather_element_positions(model, x, e);
        quads[k] = element_quadrature(model, e);
        if (projected_hessians && one_point_invariant_tet(model, e)) {
          F[in_batch] = deformation_gradient(quads[k].dN_dX[0], nodes[k]);
          batched[k] = in_batch++;
        }
      }
      compute_rotation_variant_svds(F, svds, in_batch);
      for (int k = 0; k < count; ++k) {
        if (!takes(group + k)) continue;
        if (batched[k] < 0) {
          visit(group + k, nodes[k], quads[k], nullptr);
        } else {
          const GivenDeformation given{F[batched[k]], &svds[batched[k]]};
          visit(group + k, nodes[k], quads[k], &given);
        }
      }
    }
  });
}

}  // namespace sinew
