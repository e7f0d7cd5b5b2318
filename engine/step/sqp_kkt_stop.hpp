#pragma once
// The SQP's stop at a KKT point (solve_constraints.cpp, solver.sqp_kkt_stop).
//
// After a QP solved with H = A (this step's own CHOLMOD factorisation, no curvature in it),
// taken whole, the residual at the new iterate v_k+1 is b - A v_k+1 = -J^T lambda_k up to
// round-off (the step solved A d = r_k + J^T lambda_k; not with PCG, whose solves stop at
// pcg_tolerance or a cap, where the confirming QP is a step of iterative refinement). When
// the rows at v_k+1 have the very stencils and Jacobians of the rows the QP was linearised at
// (contacts on planes: linear rows), the next QP differs from this one only in C, and
// lambda_k solves its LCP as soon as the rows' values at v_k+1 meet lambda_k's
// complementarity conditions: (v_k+1, lambda_k) is then a KKT point of the step's problem,
// and the next QP would only confirm it (a PGS sweep from lambda_k and a correction of the
// order of PGS's tolerance). This test replaces that QP; the QP before it takes that sweep
// (solve_constraints.cpp). The contact scenes of paper 000 (`sinew run`, each scene's
// frames): sphere 1 MPa 189 -> 94 QPs, collapse 318 -> 196, and the collapse's
// solve_constraints 1.670e9 -> 1.432e9 instructions (callgrind, one thread).
// Only without hyperelastic bodies: their QPs start from Newton's quadratic model, whose
// residual at v* Newton may leave nonzero (solve_newton.cpp), and the identity above fails.
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

// A row's SQP tolerance, in the units of its C: its kind's (energy, strain; contacts, friction
// and attachments share the contact tolerance).
inline double row_tolerance(const SolverDesc& cfg, RowKind kind) {
  return kind == RowKind::Energy ? cfg.sqp_tolerance : kind == RowKind::Strain ? cfg.strain_tolerance : cfg.contact_tolerance;
}

// Whether the multipliers of `last_qp` (the QP just solved, its rows linearised at v_k)
// meet the LCP conditions of `rows` (built at v_k+1): every row of `rows` that `last_qp`
// had must have its stencil and Jacobian bit for bit (else false), and carries its
// multiplier; a new row carries 0; every row of `last_qp` with a multiplier must be in
// `rows`. Each row's residual, with w = C / h (its value at v_k+1),
//   |w| inside its bounds, max(0, -w) at its lower bound, max(0, w) at its upper one,
// times h / (its kind's tolerance) must be at most solver.pgs_tolerance: PGS's own stopping
// test (solve_pgs), with the natural residual, min(that, (hi - lo) W_ii) at a bound, bounded
// above without W's diagonal. A multiplier outside its bounds (a friction row whose normal
// moved) fails, and so do a NaN multiplier or value. Scratch (kept by the caller: no
// allocation once warm): the last QP's (key, row) pairs, sorted, and the multipliers per row
// of `rows`.
bool last_multipliers_solve(const RowTable& last_qp, const RowTable& rows, double h, const SolverDesc& cfg,
                            std::vector<std::pair<uint64_t, int>>& last_rows, std::vector<double>& lambda);

}  // namespace sinew
