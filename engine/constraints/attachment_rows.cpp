#include "engine/constraints/attachment_rows.hpp"

#include <algorithm>
#include <limits>

namespace sinew {
namespace {

// Calls f(global node, weight) for the nodes that carry the vertex (tets: 4, hexes: 8).
template <typename F>
void for_vertex_nodes(const Model& model, const Attachment& a, F&& f) {
  const Body& body = model.bodies[size_t(a.body)];
  const int cell = body.embedding.cell[size_t(a.vertex)];
  const auto& weights = body.embedding.weights[size_t(a.vertex)];
  for (int k = 0; k < 8; ++k) {
    const int node = body.lattice.cells[size_t(cell)][size_t(k)];
    if (node >= 0 && weights[size_t(k)] != 0) f(body.node_offset + node, weights[size_t(k)]);
  }
}

}  // namespace

Vec3 attached_point(const Model& model, const Attachment& attachment, const VecX& x) {
  Vec3 p = Vec3::Zero();
  for_vertex_nodes(model, attachment, [&](int node, double w) { p += w * x.segment<3>(3 * node); });
  return p;
}

double add_attachment_rows(const Model& model, const std::vector<Attachment>& attachments, const VecX& x,
                           RowTable& rows) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double worst = 0;
  for (size_t i = 0; i < attachments.size(); ++i) {
    const Attachment& a = attachments[i];
    const Vec3 gap = attached_point(model, a, x) - a.target;
    worst = std::max(worst, gap.norm());
    for (int j = 0; j < 3; ++j) {
      rows.add_row(RowKind::Attachment, gap[j], -inf, inf, row_key(RowKind::Attachment, uint32_t(i), uint32_t(j)));
      for_vertex_nodes(model, a, [&](int node, double w) { rows.add_entry(node, w * Vec3::Unit(j)); });
    }
  }
  return worst;
}

}  // namespace sinew
