#pragma once
// Contact between deformable bodies: every surface vertex p of body A near the deformed
// surface of body B (A != B) yields rows, as for obstacles (contact_rows.hpp), with the
// obstacle replaced by the nearest point c = sum_k beta_k q_k of B's surface (q_k the
// nearest triangle's vertices, themselves embedded: q_k = sum_m w_km x_m):
//   normal row:  C = phi = sign |p - c| >= 0 (sign from B's pseudo-normals, < 0 inside B);
//                jac = w_n n on A's 8 nodes and -beta_k w_km n on B's (up to 24) nodes.
//                By the envelope theorem (c minimises |p - c| over the triangle) this is
//                the exact gradient with beta held fixed.
//   friction:    jac with t in place of n, value h t . (v_p - v_c): no slip between the
//                two surfaces; bounded by mu lambda_n, mu = solver.body_friction.
// B's surface is refitted (Embree RTC_BUILD_QUALITY_REFIT) at the iterate before queries.
// Both orders (A, B) and (B, A) are tested, so either surface's vertices are kept out of
// the other. Self-collision (A = B) is not handled.
#include "engine/collision/body_surfaces.hpp"
#include "engine/constraints/contact_rows.hpp"

namespace sinew {

// Partner id of body b in row keys: obstacles come first.
uint32_t body_partner(const Model& model, int b);

struct BodyContactRowBuffers;  // body_contact_rows.cpp

// `storage`: buffers kept from call to call (kept_storage.hpp); without, this thread's.
ContactRowsResult add_body_contact_rows(const Model& model, const VecX& x, const VecX& v,
                                        const std::vector<uint64_t>& keep, BodySurfaces& surfaces, RowTable& rows,
                                        ContactSearch search = ContactSearch::BroadPhase,
                                        KeptStorage<BodyContactRowBuffers>* storage = nullptr);

}  // namespace sinew
