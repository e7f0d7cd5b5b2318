#include "engine/constraints/body_contact_rows.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "engine/constraints/contact_candidates.hpp"

namespace sinew {

uint32_t body_partner(const Model& model, int b) { return static_cast<uint32_t>(model.obstacles.size() + b); }

namespace body_contact_detail {

struct SurfaceProbe {
  int vertex = 0;
  MeshDistance distance;
  Vec3 velocity;  // v_p - v_c
};

// Stencil of one row: A's vertex cell with w_n d, B's triangle cells with -beta_k w_km d,
// B's repeated nodes merged (the solver expects each node once per row).
class RowStencil {
 public:
  void clear() { m_nodes.clear(), m_jac.clear(); }
  void add(int node, const Vec3& d) {
    for (size_t i = 0; i < m_nodes.size(); ++i)
      if (m_nodes[i] == node) {
        m_jac[i] += d;
        return;
      }
    m_nodes.push_back(node);
    m_jac.push_back(d);
  }
  void append_to(RowTable& rows) const {
    for (size_t i = 0; i < m_nodes.size(); ++i) rows.add_entry(m_nodes[i], m_jac[i]);
  }

 private:
  std::vector<int> m_nodes;
  std::vector<Vec3> m_jac;
};

}  // namespace body_contact_detail

// add_body_contact_rows' kept storage (kept_storage.hpp).
struct BodyContactRowBuffers {
  std::vector<uint32_t> first_vertex;
  std::vector<Aabb> bounds;
  std::vector<char> refitted;
  std::vector<int> candidates;
  std::vector<uint64_t> candidate_marks;  // gather_candidates' scratch
  std::vector<body_contact_detail::SurfaceProbe> probes;
  body_contact_detail::RowStencil stencil;
};

namespace {

using body_contact_detail::RowStencil;
using body_contact_detail::SurfaceProbe;

void build_stencil(const Body& a, int vertex, const Body& b, const MeshSdf& surface, const MeshDistance& d,
                   const Vec3& direction, RowStencil& stencil) {
  stencil.clear();
  const auto& cell = a.lattice.cells[a.embedding.cell[vertex]];
  for (int n = 0; n < 8; ++n)
    if (cell[n] >= 0) stencil.add(a.node_offset + cell[n], a.embedding.weights[vertex][n] * direction);
  const auto& tri = surface.triangles()[d.triangle];
  for (int k = 0; k < 3; ++k) {
    const int q = tri[k];
    const auto& qcell = b.lattice.cells[b.embedding.cell[q]];
    for (int m = 0; m < 8; ++m)
      if (qcell[m] >= 0) stencil.add(b.node_offset + qcell[m], -d.bary[k] * b.embedding.weights[q][m] * direction);
  }
}

// Velocity of the nearest point c = sum_k beta_k q_k.
Vec3 surface_point_velocity(const Body& b, const MeshSdf& surface, const MeshDistance& d, const VecX& x,
                            const VecX& v) {
  Vec3 vc = Vec3::Zero(), p, vq;
  const auto& tri = surface.triangles()[d.triangle];
  for (int k = 0; k < 3; ++k) {
    embedded_point(b, tri[k], x, v, p, vq);
    vc += d.bary[k] * vq;
  }
  return vc;
}

}  // namespace

ContactRowsResult add_body_contact_rows(const Model& model, const VecX& x, const VecX& v,
                                        const std::vector<uint64_t>& keep, BodySurfaces& surfaces, RowTable& rows,
                                        ContactSearch search, KeptStorage<BodyContactRowBuffers>* storage) {
  ContactRowsResult result;
  const int nb = static_cast<int>(model.bodies.size());
  if (nb < 2) return result;
  const double h = model.h, mu = model.solver.body_friction;
  BodyContactRowBuffers& buffers = kept_or_thread_local(storage);
  std::vector<uint32_t>& first_vertex = buffers.first_vertex;
  std::vector<Aabb>& bounds = buffers.bounds;
  std::vector<char>& refitted = buffers.refitted;
  std::vector<int>& candidates = buffers.candidates;
  std::vector<SurfaceProbe>& probes = buffers.probes;
  RowStencil& stencil = buffers.stencil;
  first_vertex.assign(nb + 1, 0);
  for (int b = 0; b < nb; ++b)
    first_vertex[b + 1] = first_vertex[b] + static_cast<uint32_t>(model.bodies[b].embedding.cell.size());
  bounds.resize(nb);
  for (int b = 0; b < nb; ++b) bounds[b] = body_surface_bounds(x, model.bodies[b]);
  refitted.assign(nb, 0);
  for (int a = 0; a < nb; ++a) {
    const Body& body_a = model.bodies[a];
    const double margin = contact_margin(model, a);
    for (int b = 0; b < nb; ++b) {
      if (b == a || (model.asleep(a) && model.asleep(b))) continue;  // two sleepers: neither can move
      const Body& body_b = model.bodies[b];
      const uint32_t partner = body_partner(model, b);
      // Broad phase: A's cells whose surface bounds come within the margin of B's.
      // One captured pointer: small enough for std::function to hold without allocating.
      const struct {
        const Aabb& bounds;
        double margin;
      } query{bounds[b], margin};
      const auto near = [q = &query](const Aabb& box) { return box_distance(box, q->bounds) < q->margin; };
      gather_candidates(x, body_a, near, search == ContactSearch::BruteForce, first_vertex[a], partner, keep,
                        buffers.candidate_marks, candidates);
      if (candidates.empty()) continue;
      if (!refitted[b]) deformed_surface(model, b, x, surfaces);
      refitted[b] = 1;
      const MeshSdf& surface = *surfaces.mesh[b];
      // Nearest point on B for each candidate (unbounded search, so that the sign is right
      // even for a vertex deep inside B); one task per slot.
      probes.resize(candidates.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 256), [&](const auto& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          Vec3 p, vp;
          embedded_point(body_a, candidates[i], x, v, p, vp);
          const MeshDistance d =
              search == ContactSearch::BruteForce ? surface.distance_brute_force(p) : surface.distance(p);
          probes[i] = {candidates[i], d, d.triangle >= 0 ? Vec3(vp - surface_point_velocity(body_b, surface, d, x, v)) : vp};
        }
      });
      result.candidates += static_cast<int>(probes.size());
      for (const SurfaceProbe& probe : probes) {
        if (probe.distance.triangle < 0) continue;
        const uint32_t id = first_vertex[a] + probe.vertex;
        const uint64_t key = contact_key(id, partner);
        const double phi = probe.distance.phi;
        result.deepest = std::max(result.deepest, -phi);
        if (phi >= margin && !std::binary_search(keep.begin(), keep.end(), key)) continue;
        const int normal = rows.add_row(RowKind::Contact, phi, 0.0, 1e300, key);
        build_stencil(body_a, probe.vertex, body_b, surface, probe.distance, probe.distance.normal, stencil);
        stencil.append_to(rows);
        if (mu <= 0) continue;
        Vec3 t[2];
        contact_tangents(probe.distance.normal, t[0], t[1]);
        for (int j = 0; j < 2; ++j) {
          rows.add_row(RowKind::Friction, h * t[j].dot(probe.velocity), -1e300, 1e300, friction_key(id, partner, j));
          rows.normal_row.back() = normal;
          rows.mu.back() = mu;
          build_stencil(body_a, probe.vertex, body_b, surface, probe.distance, t[j], stencil);
          stencil.append_to(rows);
        }
      }
    }
  }
  return result;
}

}  // namespace sinew
