#pragma once
// Energy-limiting constraint of paper 000, section 4:
//   C = 1 - Ue / Umax >= 0                                            (eq. 14)
//   Ue = sum_q e(eps_q) det(F), e = sigma : eps, eps from R^T G - I   (eqs. 11-13)
// which for the hex8 element is Ue = u^T Ke u with u = R^T x - X.
//
// Jacobians, with the rotation R held fixed as the paper does:
//   exact  (eqs. 15-18): dC/dx = -(2 / Umax) R Ke u
//   warped (the comparison of section 6.2): the warped elastic force f_e / Umax
//          = -(1 / Umax) R Ke u. It has the direction of the exact gradient but half its
//          length, because f_e is the gradient of 1/2 u^T Ke u while Ue = u^T Ke u: the
//          linearised constraint then overshoots, which is what slows SQP down.
#include "engine/constraints/energy_screen.hpp"
#include "engine/constraints/row_table.hpp"
#include "engine/core/kept_storage.hpp"
#include "engine/model.hpp"

namespace sinew {

enum class EnergyJacobian { Exact, Warped };

struct EnergyRowBuffers;  // energy_limit.cpp

struct EnergyLimitEval {
  double value = 0;   // C
  double ratio = 0;   // Ue / Umax
  Vec24 jac;          // dC/dx over the 8 nodes (node-major)
};

// Ku = Ke u of the element (hex8 or tet4, padded to 24 entries: element_kernels.hpp).
EnergyLimitEval evaluate_energy_limit(const Vec24& Ku, const Mat3& R, const Vec24& u,
                                      double Umax, EnergyJacobian mode);

// Adds a row for every limited element whose Ue/Umax exceeds 1 - margin at x, or whose key
// is in `keep` (rows that carried force earlier in this step). Rotations come from x.
// Returns the worst Ue/Umax - 1 over all limited elements (-1 when none). With a screen
// (energy_screen.hpp), elements the bound against their last exact evaluation places below
// 1 - margin are skipped, the others evaluated (and their references moved to x): the same
// rows, and the same worst value whenever it is above -margin (below, an upper bound, still
// below -margin: callers only compare it with positive tolerances and report its positive
// part).
// `storage`: buffers kept from call to call (kept_storage.hpp); without, this thread's.
double add_energy_limit_rows(const Model& model, const VecX& x, double margin,
                             const std::vector<uint64_t>& keep, RowTable& rows, EnergyScreen* screen = nullptr,
                             KeptStorage<EnergyRowBuffers>* storage = nullptr);

// Worst Ue/Umax - 1 over limited elements at x (-1 when none); no rows.
double worst_energy_violation(const Model& model, const VecX& x);

}  // namespace sinew
