#pragma once
// Broad phase shared by obstacle and body-vs-body contact rows: which surface vertices of a
// body are worth an exact distance query.
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/model.hpp"

namespace sinew {

// Node bounds of the body / one cell at x, grown by the spread of the surface vertices
// they carry (SurfaceCells): every such vertex lies inside.
Aabb body_surface_bounds(const VecX& x, const Body& body);
Aabb cell_surface_bounds(const VecX& x, const Body& body, int cell);

// Surface vertices of `body` in the cells whose bounds pass `near` (all of them when
// `everything`), plus those whose contact key with `partner` (an obstacle index, or
// obstacles + body for body contacts) is in `keep`: ascending, without repeats. Vertex ids
// in keys start at first_vertex for this body. `marks`: scratch, one bit per surface vertex
// (kept by the caller: no allocation once sized).
void gather_candidates(const VecX& x, const Body& body, const std::function<bool(const Aabb&)>& near,
                       bool everything, uint32_t first_vertex, uint32_t partner, const std::vector<uint64_t>& keep,
                       std::vector<uint64_t>& marks, std::vector<int>& out);

// p = sum_n w_n x_n and its velocity for surface vertex i of `body`.
void embedded_point(const Body& body, int i, const VecX& x, const VecX& v, Vec3& p, Vec3& vp);

}  // namespace sinew
