#pragma once
// The hyperelastic elements' part of Newton's incremental potential (solve_newton.cpp) in one
// pass over the element schedule: energies, gradient and, when asked, Hessians. Its own file
// so that sinew_bench_assembly can time the pass alone.
#include <vector>

#include "engine/core/types.hpp"
#include "engine/model.hpp"

namespace sinew {

struct KeptTetHessians;

// Per-element energies and squared force norms |dPsi_e/dx|^2, the gradient over free DOFs
// (dPsi/dx, free nodes only) and, if `values` is not null, h^2 times the element Hessians
// (projected, or exact if `exact`) scattered into a matrix of the system pattern.
// The elements' gradients go to `node_gradients` (one 3-vector per entry of the model's
// node_elements, where sum_by_node reads a node's terms in a row) and are summed by node
// afterwards (node_elements.hpp: each node's in element order), so that without `values`
// nothing is shared between elements and they run in one parallel loop in any order, not
// colour by colour: the pass of the line search's trials, the same bits as the assembly's.
// kept (with `values`, projected Hessians): one-point tets of invariant materials whose F
// moved by at most reuse_tolerance (entrywise) since their Hessian was formed keep it
// (kept_tet_hessians.hpp); the others form theirs afresh; the kept sum is added to `values`.
// overwrite: the values are written, not added to (only where keeps_every_hessian).
void hyperelastic_derivatives(const Model& model, const VecX& x, bool exact, std::vector<double>& energy,
                              std::vector<double>& force2, VecX& gradient, double* values,
                              std::vector<Vec3>& node_gradients, KeptTetHessians* kept = nullptr,
                              double reuse_tolerance = 0, bool overwrite = false);

// Sizes `kept` for the model (dropping what it holds if the pattern or h changed) and tells
// whether every hyperelastic element keeps its Hessian there (one-point tets of invariant
// materials), so that a pass can overwrite the values instead of adding to zeros.
bool keeps_every_hessian(const Model& model, KeptTetHessians& kept);
// Whether any does (else a pass leaves `kept` unused).
bool keeps_any_hessian(const Model& model, KeptTetHessians& kept);

}  // namespace sinew
