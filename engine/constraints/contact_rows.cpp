#include "engine/constraints/contact_rows.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>

#include "engine/collision/obstacle_motion.hpp"
#include "engine/collision/obstacle_sdf.hpp"
#include "engine/constraints/contact_candidates.hpp"

namespace sinew {

void contact_tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 e = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitZ();
  t1 = e.cross(n).normalized();
  t2 = n.cross(t1);
}

double contact_margin(const Model& model, int body) {
  const double m = model.solver.contact_margin;
  return m >= 0 ? m : 0.25 * model.bodies[body].lattice.cell_size;
}

uint64_t contact_key(uint32_t vertex, uint32_t obstacle) { return row_key(RowKind::Contact, vertex, obstacle); }

uint64_t friction_key(uint32_t vertex, uint32_t obstacle, int tangent) {
  return row_key(RowKind::Friction, vertex, 2 * obstacle + tangent);
}

namespace contact_rows_detail {

// A surface vertex tested against one obstacle.
struct Probe {
  int vertex = 0;  // index in the body's surface
  SdfSample sdf;
  Vec3 velocity;   // v_p = sum_n w_n v_n at the iterate
};

}  // namespace contact_rows_detail

// add_contact_rows' kept storage (kept_storage.hpp).
struct ContactRowBuffers {
  std::vector<int> candidates;
  std::vector<contact_rows_detail::Probe> probes, representatives;
  std::vector<uint64_t> candidate_marks;  // gather_candidates' scratch
  std::vector<int> site_best;  // per contact site, its deepest probe so far (-1: none)
  std::vector<uint32_t> sites;  // per probe, its contact site
};

namespace {

using contact_rows_detail::Probe;

// Signed distance and velocity of each candidate; each probe is written by one task only.
void evaluate_probes(const VecX& x, const VecX& v, const Body& body, const ObstacleDesc& ob,
                     const Vec3& origin, const std::vector<int>& candidates, bool brute_force,
                     std::vector<Probe>& probes) {
  probes.resize(candidates.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 512), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      Vec3 p, vp;
      embedded_point(body, candidates[i], x, v, p, vp);
      probes[i] = {candidates[i], obstacle_sdf(ob, origin, p, brute_force), vp};
    }
  });
}

// One row with stencil w_n d over the vertex's cell. Zero weights are left out: a vertex
// on a node of a tet mesh has one non-zero weight of four, and a row of one node costs the
// constraint solve 3 columns of H^-1 shared with the vertex's friction rows (delassus.hpp).
void add_vertex_row(RowTable& rows, RowKind kind, double value, double lo, double hi, uint64_t key,
                    const Body& body, int vertex, const Vec3& d) {
  rows.add_row(kind, value, lo, hi, key);
  const auto& cell = body.lattice.cells[body.embedding.cell[vertex]];
  const auto& w = body.embedding.weights[vertex];
  for (int n = 0; n < 8; ++n)
    if (cell[n] >= 0 && w[n] != 0) rows.add_entry(body.node_offset + cell[n], w[n] * d);
}

// Which eighth of its cell a surface vertex sits in (by its rest position).
// Tet bodies: the tet's node with the largest weight instead (a vertex on a node of a tet
// mesh is then a site of its own).
int cell_octant(const Body& body, int vertex) {
  const int cell = body.embedding.cell[vertex];
  if (body.element_type == ElementType::Tet4) {
    const auto& w = body.embedding.weights[vertex];
    return static_cast<int>(std::max_element(w.begin(), w.begin() + 4) - w.begin());
  }
  const auto& g = body.lattice.cell_coords[cell];
  const Vec3 centre = body.lattice.origin + body.lattice.cell_size * Vec3(g[0] + 0.5, g[1] + 0.5, g[2] + 0.5);
  const Vec3 d = body.rest_surface.vertices[vertex] - centre;
  return (d.x() > 0) * 4 + (d.y() > 0) * 2 + (d.z() > 0);
}

// A contact site is an eighth of a lattice cell; in a tet body, the node that carries most
// of the vertex (the tets around a node share it, so its vertices make one site).
uint32_t contact_site(const Body& body, int vertex) {
  if (body.element_type == ElementType::Tet4)
    return static_cast<uint32_t>(body.lattice.cells[body.embedding.cell[vertex]][cell_octant(body, vertex)]);
  return static_cast<uint32_t>(8 * body.embedding.cell[vertex] + cell_octant(body, vertex));
}

// The number of contact sites of a body: the range of contact_site.
size_t contact_site_count(const Body& body) {
  return body.element_type == ElementType::Tet4 ? static_cast<size_t>(body.num_nodes())
                                                : 8 * static_cast<size_t>(body.num_elements());
}

// The probes that get rows: per site (cell, octant) the deepest vertex (ties: the lowest
// index), plus every vertex whose row is kept (it carried force earlier in this step or
// the last). The lattice cannot resolve contact finer than its cells' trilinear field:
// a row per vertex only adds nearly dependent copies that cost a solve column each (and
// slow PGS). When the deepest vertex of a site changes between SQP iterations, the new
// one joins and the old one stays (kept), so the rows still converge.
// `probes` come in ascending vertex order (gather_candidates), and so do the
// representatives: the first of a site's deepest wins a tie. `site_best`: scratch, -1 on
// entry and on return; `sites`: scratch.
void representative_probes(const Body& body, const std::vector<Probe>& probes, uint32_t first_vertex,
                           uint32_t obstacle, const std::vector<uint64_t>& keep, std::vector<int>& site_best,
                           std::vector<uint32_t>& sites, std::vector<Probe>& out) {
  if (site_best.size() < contact_site_count(body)) site_best.resize(contact_site_count(body), -1);
  const int count = static_cast<int>(probes.size());
  sites.resize(count);
  for (int i = 0; i < count; ++i) {
    sites[i] = contact_site(body, probes[i].vertex);
    int& best = site_best[sites[i]];
    if (best < 0 || probes[i].sdf.phi < probes[best].sdf.phi) best = i;
  }
  out.clear();
  for (int i = 0; i < count; ++i) {
    const Probe& p = probes[i];
    if (site_best[sites[i]] == i ||
        std::binary_search(keep.begin(), keep.end(), contact_key(first_vertex + p.vertex, obstacle)))
      out.push_back(p);
  }
  for (int i = 0; i < count; ++i) site_best[sites[i]] = -1;
}

// Whether the vertex's embedding weighs some free node: a vertex held by fixed nodes alone
// (the base of a column standing on the ground) gets no row, which could only be empty.
bool moves_free_node(const Model& model, const Body& body, int vertex) {
  const auto& cell = body.lattice.cells[body.embedding.cell[vertex]];
  const auto& w = body.embedding.weights[vertex];
  for (int n = 0; n < 8; ++n)
    if (cell[n] >= 0 && w[n] != 0 && model.free_index[body.node_offset + cell[n]] >= 0) return true;
  return false;
}

}  // namespace

ContactRowsResult add_contact_rows(const Model& model, double t_end, const VecX& x, const VecX& v,
                                   const std::vector<uint64_t>& keep, RowTable& rows, ContactSearch search,
                                   KeptStorage<ContactRowBuffers>* storage) {
  ContactRowsResult result;
  const double h = model.h;
  ContactRowBuffers& buffers = kept_or_thread_local(storage);
  std::vector<int>& candidates = buffers.candidates;
  std::vector<Probe>& probes = buffers.probes;
  std::vector<Probe>& representatives = buffers.representatives;
  for (uint32_t k = 0; k < model.obstacles.size(); ++k) {
    const ObstacleDesc& ob = model.obstacles[k];
    const Vec3 origin = obstacle_position(ob, t_end);
    const Vec3 v_obstacle = obstacle_velocity(ob, t_end - h, t_end);
    uint32_t first_vertex = 0;
    for (int b = 0; b < static_cast<int>(model.bodies.size()); ++b) {
      const Body& body = model.bodies[b];
      // A sleeping body's nodes are not unknowns: a row on it alone would be empty (and
      // a moving obstacle near it wakes it before the step, engine/sleep/sleep.hpp).
      if (model.asleep(b)) {
        first_vertex += static_cast<uint32_t>(body.embedding.cell.size());
        continue;
      }
      const double margin = contact_margin(model, b);
      // Broad phase: cells whose surface bounds may come within the margin of the obstacle.
      // One captured pointer: small enough for std::function to hold without allocating.
      const struct {
        const ObstacleDesc& ob;
        const Vec3& origin;
        double margin;
      } query{ob, origin, margin};
      const auto near = [q = &query](const Aabb& box) { return obstacle_distance_bound(q->ob, q->origin, box) < q->margin; };
      gather_candidates(x, body, near, search == ContactSearch::BruteForce, first_vertex, k, keep, buffers.candidate_marks,
                        candidates);
      evaluate_probes(x, v, body, ob, origin, candidates, search == ContactSearch::BruteForce, probes);
      result.candidates += static_cast<int>(probes.size());
      representative_probes(body, probes, first_vertex, k, keep, buffers.site_best, buffers.sites, representatives);
      for (const Probe& probe : representatives) {
        const uint32_t id = first_vertex + probe.vertex;
        const uint64_t key = contact_key(id, k);
        result.deepest = std::max(result.deepest, -probe.sdf.phi);
        if (probe.sdf.phi >= margin && !std::binary_search(keep.begin(), keep.end(), key)) continue;
        if (!moves_free_node(model, body, probe.vertex)) continue;
        const int normal = rows.size();
        add_vertex_row(rows, RowKind::Contact, probe.sdf.phi, 0.0, 1e300, key, body, probe.vertex, probe.sdf.normal);
        if (ob.friction <= 0) continue;
        Vec3 t[2];
        contact_tangents(probe.sdf.normal, t[0], t[1]);
        for (int j = 0; j < 2; ++j) {
          const double slip = t[j].dot(probe.velocity - v_obstacle);
          add_vertex_row(rows, RowKind::Friction, h * slip, -1e300, 1e300, friction_key(id, k, j), body,
                         probe.vertex, t[j]);
          rows.normal_row.back() = normal;
          rows.mu.back() = ob.friction;
        }
      }
      first_vertex += static_cast<uint32_t>(body.embedding.cell.size());
    }
  }
  return result;
}

}  // namespace sinew
