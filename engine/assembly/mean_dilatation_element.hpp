#pragma once
// A hex8 hyperelastic element whose volume term sees the element's mean dilatation (Nagtegaal
// et al. 1974; Simo, Taylor and Pister 1985), for materials Psi = f(Ic) + g(J):
//   Psi_e = sum_q w f(Ic_q) + V g(Jbar),   Jbar = (1/V) sum_q w J_q,   V = sum_q w
// Jbar is the element's current volume over its rest volume (2x2x2 Gauss integrates the
// trilinear map's J exactly). Why: at nu -> 1/2, g stiffens J at each of the 8 points, more
// volume constraints than a lattice has DOFs, so the mesh locks; one per element does not
// (the scrambled cube, tests/engine/scenes/test_paper003_scrambled_cube.cpp). The price: a
// point may invert inside an element of the right volume (Ic cannot tell). Derivatives:
//   dPsi_e/dx = sum_q w B_q^T vec(2 f'_q F_q + g'(Jbar) cof F_q)
//   d2Psi_e/dx2 = sum_q w B_q^T D_q B_q + g''(Jbar)/V b b^T,   b = sum_q w B_q^T vec(cof F_q)
// where D_q is the invariant Hessian (invariant_material.hpp) with f'_q, f''_q, g' = g'(Jbar)
// and g'' = 0. Projected: each D_q by its closed-form eigensystem and g'' clamped at 0, a sum
// of PSD terms, so PSD (not the nearest PSD matrix of the whole sum: a bound that keeps
// Newton's direction a descent direction).
#include "engine/assembly/element_kernels.hpp"
#include "engine/materials/invariant_material.hpp"

namespace sinew {

// +infinity where the material is undefined at Jbar (neo_hookean with Jbar <= 0).
double mean_dilatation_element_energy(const InvariantMaterial& material, const ElementQuadrature& quad,
                                      const ElementNodes& nodes);

// Returns the energy; writes the gradient and, if hessian != nullptr, the projected Hessian
// (exact == false) or the exact one.
double mean_dilatation_element_derivatives(const InvariantMaterial& material, const ElementQuadrature& quad,
                                           const ElementNodes& nodes, bool exact, Vec24& gradient,
                                           Mat24* hessian);

}  // namespace sinew
