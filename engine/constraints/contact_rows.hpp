#pragma once
// Frictional contact of embedded surface vertices with obstacles, as rows of the one
// constraint table (paper 000, section 5: non-penetration and friction are solved in the
// same projected Gauss-Seidel loop as the energy limits).
//
// For a surface vertex p = sum_n w_n x_n (trilinear weights over the 8 nodes of its cell)
// and an obstacle with signed distance phi and unit normal n at the end of the step:
//   normal row:   C = phi(p(x)) >= 0,    jac_n = w_n n,   lambda in [0, inf)
//                 value = phi at the iterate x_k = x0 + h v_k, position level as in eq. 22,
//                 so the solver enforces phi_k + h J (v - v_k) >= 0: no penetration at the
//                 end of the step, and a vertex above the surface may close the gap.
//   friction rows (tangents t1, t2 of n):  jac_n = w_n t,  |lambda| <= mu lambda_normal
//                 value = h (t . v_p(v_k) - t . v_obstacle), so that the solver's
//                 W lambda + c = 0 with c = value / h + J (v_base - v_k) reads
//                 t . v_p(v) = t . v_obstacle: no slip relative to the obstacle.
// Lambda is an impulse along jac (v = v* + A^-1 J^T lambda). Friction is the box
// approximation of the Coulomb cone (two rows, each bounded by mu lambda_n, updated inside
// PGS): it allows up to sqrt(2) mu lambda_n along a diagonal of (t1, t2).
#include <cstdint>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/core/kept_storage.hpp"
#include "engine/model.hpp"

namespace sinew {

// Tangents of unit normal n, a function of n alone that varies continuously with it except
// where |n_x| crosses 0.9 (so that warm-started friction multipliers keep their meaning
// from step to step): e = x, or z when |n_x| >= 0.9; t1 = (e x n)/|e x n|, t2 = n x t1.
// For n = +y: t1 = +z, t2 = +x.
void contact_tangents(const Vec3& n, Vec3& t1, Vec3& t2);

// Distance below which a vertex of body b gets rows: solver.contact_margin, or a quarter of
// the body's cell size when that is negative (the default).
double contact_margin(const Model& model, int body);

// Row keys: vertex ids count surface vertices over all bodies in order; friction sub-rows
// 2 k and 2 k + 1 for obstacle k.
uint64_t contact_key(uint32_t vertex, uint32_t obstacle);
uint64_t friction_key(uint32_t vertex, uint32_t obstacle, int tangent);

// How candidate vertices are found: the broad phase (body bounds, cell bounds, BVH for
// meshes), or every vertex against every triangle (the slow path tests and benchmarks
// compare with; same rows).
enum class ContactSearch { BroadPhase, BruteForce };

struct ContactRowBuffers;  // contact_rows.cpp

struct ContactRowsResult {
  double deepest = 0;   // deepest penetration max(0, -phi) over the vertices tested, m
  int candidates = 0;   // vertices that passed the broad phase
};

// Appends the rows above for every (vertex, obstacle) pair with phi < margin at positions
// x (obstacles placed at time t_end), or whose normal key is in `keep` (sorted): rows that
// carried force earlier in the step stay. v is the velocity iterate v_k. Friction rows are
// left out when mu = 0. Broad phase: body node bounds, then cell bounds (SurfaceCells),
// before any vertex is tested. Rows come in a fixed order (obstacle, body, vertex), with
// each normal row followed by its two friction rows; vertices are tested in parallel.
// `storage`: buffers kept from call to call (kept_storage.hpp); without, this thread's.
ContactRowsResult add_contact_rows(const Model& model, double t_end, const VecX& x, const VecX& v,
                                   const std::vector<uint64_t>& keep, RowTable& rows,
                                   ContactSearch search = ContactSearch::BroadPhase,
                                   KeptStorage<ContactRowBuffers>* storage = nullptr);

}  // namespace sinew
