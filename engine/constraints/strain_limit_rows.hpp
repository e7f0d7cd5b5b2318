#pragma once
// Rows of the strain-limit constraints (paper 001; per-tet math in strain_limit.hpp) for
// every tet of the bodies that have strain limits.
#include "engine/constraints/row_table.hpp"
#include "engine/constraints/strain_limit.hpp"
#include "engine/core/kept_storage.hpp"
#include "engine/model.hpp"

namespace sinew {

struct StrainRowBuffers;  // strain_limit_rows.cpp

StrainLimitSpec strain_limit_spec(const StrainLimitDesc& desc);

// Adds a row for every constraint with C < margin at x, or whose key is in `keep` (sorted;
// rows that carried force earlier in this step). Returns the worst violation max(-C) over
// all limited tets (-1 when none). Their curvature blocks come later, once PGS has said
// which rows carry force (below).
// `storage`: buffers kept from call to call (kept_storage.hpp); without, this thread's.
// Deferred (with a `storage`): the rows' Jacobians are left zero until
// complete_strain_limit_jacobians (a line-search trial needs the values alone, and most
// trials are not linearised at).
// `cut_gaps` (per element, from strain_pair_cut_gaps below): the gap under which each tet's
// pairs get their cuts (strain_limit.hpp): empty or one per element. Null or empty: cuts
// wherever a pair is within kStrainLimitBlendGap.
enum class StrainJacobians { Now, Deferred };
double add_strain_limit_rows(const Model& model, const VecX& x, double margin,
                             const std::vector<uint64_t>& keep, RowTable& rows,
                             KeptStorage<StrainRowBuffers>* storage = nullptr,
                             StrainJacobians jacobians = StrainJacobians::Now,
                             const std::vector<double>* cut_gaps = nullptr);

// Per element, the gap under which its pairs get cuts, from `v_start` (3 per free node), the
// step's start velocities: they gate the cuts by how far they move F over the step,
// delta = h |L| for the velocity gradient L = sum_a v_a dN_a^T (Frobenius; spin included,
// which errs towards more cuts: a spin-free measure, |sym(U^T L V)|, took the flat finger's
// SQP from 262 to 285 iterations over 120 frames, against 321 without cuts; kinematic nodes
// count as still). A linearisation misses a near-equal pair's largest stretch by
// ~delta^2 / gap, so a pair gets its cuts only where that could reach a quarter of
// solver.strain_tolerance: gap < 4 delta^2 / tolerance. A body at rest has none: there the
// cuts only make the LCP degenerate (their gradients and the pair's rows are dependent where
// the stretches meet) and PGS slower (the side-pressed finger at rest kept ~8, and 3-17
// sweeps a step instead of 1). Computed once a step (the start velocities do not change
// within it), not at each of its row builds. 0 for tets without limits; empty `out` if
// `v_start` has the wrong size (no gate).
void strain_pair_cut_gaps(const Model& model, const VecX& v_start, std::vector<double>& out);

// Sets the Jacobians that the last add_strain_limit_rows with this storage left zero, if it
// was deferred (from that build's SVDs: `rows` must hold that build's rows where it put
// them, and may have gained rows after them); nothing when none are pending.
void complete_strain_limit_jacobians(const Model& model, RowTable& rows,
                                     KeptStorage<StrainRowBuffers>* storage = nullptr);

// Curvature blocks (strain_limit_curvature.hpp) of the strain rows with lambda > 0 that
// have none yet, at x (the rows' linearisation point). Only those enter SQP's Hessian
// (solve_constraints.cpp), and a block costs 10 evaluations of the tet's rows: most rows
// near their limits carry no force.
void add_strain_limit_curvatures(const Model& model, const VecX& x, RowTable& rows);

// The same worst violation, without rows.
double worst_strain_limit_violation(const Model& model, const VecX& x);

}  // namespace sinew
