#include "engine/constraints/contact_candidates.hpp"

#include <algorithm>
#include <bit>

#include "engine/constraints/row_table.hpp"

namespace sinew {
namespace {

Aabb node_bounds(const VecX& x, int first, int count) {
  Aabb box;
  for (int n = first; n < first + count; ++n) box.extend(x.segment<3>(3 * n));
  return box;
}

// Vertex index of a kept contact key with `partner` within [first, first + count), or -1.
// Keys are (kind << 60) ^ (vertex << 24) ^ partner (row_key) with partner < 2^24.
int kept_vertex(uint64_t key, uint32_t partner, uint32_t first, uint32_t count) {
  if (row_key_kind(key) != RowKind::Contact || row_key_second(key) != partner) return -1;
  const uint64_t vertex = row_key_first(key);
  return vertex >= first && vertex < uint64_t(first) + count ? int(vertex - first) : -1;
}

}  // namespace

Aabb body_surface_bounds(const VecX& x, const Body& body) {
  return grow_by_spread(node_bounds(x, body.node_offset, body.num_nodes()), body.surface_cells.max_spread);
}

Aabb cell_surface_bounds(const VecX& x, const Body& body, int cell) {
  Aabb box;
  for (int n : body.lattice.cells[cell])
    if (n >= 0) box.extend(x.segment<3>(3 * (body.node_offset + n)));
  return grow_by_spread(box, body.surface_cells.spread[cell]);
}

void gather_candidates(const VecX& x, const Body& body, const std::function<bool(const Aabb&)>& near,
                       bool everything, uint32_t first_vertex, uint32_t partner, const std::vector<uint64_t>& keep,
                       std::vector<uint64_t>& marks, std::vector<int>& out) {
  const SurfaceCells& sc = body.surface_cells;
  const uint32_t count = static_cast<uint32_t>(body.embedding.cell.size());
  out.clear();
  if (everything) {
    for (uint32_t i = 0; i < count; ++i) out.push_back(static_cast<int>(i));
    return;
  }
  // A bit per vertex, read back in order: ascending and without repeats with no sort (the
  // pressed finger: a few hundred candidates, 3-7 builds a step).
  marks.assign((count + 63) / 64, 0);
  const auto mark = [&](int i) { marks[i >> 6] |= uint64_t{1} << (i & 63); };
  for (uint64_t key : keep)
    if (const int i = kept_vertex(key, partner, first_vertex, count); i >= 0) mark(i);
  if (near(body_surface_bounds(x, body))) {
    for (int c = 0; c < body.num_elements(); ++c) {
      if (sc.begin[c] == sc.begin[c + 1] || !near(cell_surface_bounds(x, body, c))) continue;
      for (int k = sc.begin[c]; k < sc.begin[c + 1]; ++k) mark(sc.vertices[k]);
    }
  }
  for (size_t w = 0; w < marks.size(); ++w)
    for (uint64_t bits = marks[w]; bits != 0; bits &= bits - 1)
      out.push_back(static_cast<int>(64 * w) + std::countr_zero(bits));
}

void embedded_point(const Body& body, int i, const VecX& x, const VecX& v, Vec3& p, Vec3& vp) {
  const auto& cell = body.lattice.cells[body.embedding.cell[i]];
  const auto& w = body.embedding.weights[i];
  p.setZero();
  vp.setZero();
  for (int n = 0; n < 8; ++n) {
    if (cell[n] < 0) continue;
    const Eigen::Index at = 3 * (Eigen::Index(body.node_offset) + cell[n]);
    p += w[n] * x.segment<3>(at);
    vp += w[n] * v.segment<3>(at);
  }
}

}  // namespace sinew
