#include "engine/collision/mesh_sdf.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <utility>

#include "engine/geometry/obj_reader.hpp"

namespace sinew {

MeshSdf::MeshSdf(const TriMesh& mesh, bool deforming) : m_bvh(mesh.vertices, mesh.triangles, deforming) {
  const size_t nt = mesh.triangles.size(), nv = mesh.vertices.size();
  // Edge neighbours: the two triangles of each undirected edge.
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;  // edge -> (triangle, k)
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      edges[std::minmax(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3])].emplace_back(int(t), k);
  m_neighbour.assign(nt, {-1, -1, -1});
  for (const auto& [edge, sides] : edges)
    if (sides.size() == 2) {
      m_neighbour[sides[0].first][sides[0].second] = sides[1].first;
      m_neighbour[sides[1].first][sides[1].second] = sides[0].first;
    }
  // One-ring of each vertex.
  m_ring_begin.assign(nv + 1, 0);
  for (const auto& f : mesh.triangles)
    for (int v : f) ++m_ring_begin[v + 1];
  for (size_t v = 0; v < nv; ++v) m_ring_begin[v + 1] += m_ring_begin[v];
  m_ring.resize(3 * nt);
  std::vector<int> next(m_ring_begin.begin(), m_ring_begin.end() - 1);
  for (size_t t = 0; t < nt; ++t)
    for (int v : mesh.triangles[t]) m_ring[next[v]++] = int(t);
}

Vec3 MeshSdf::face_normal(int t) const {
  const auto& f = triangles()[t];
  const auto& v = vertices();
  return (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).normalized();
}

// Face: its normal. Edge: the sum of its two faces' normals. Vertex: the sum of its faces'
// normals weighted by their interior angle at the vertex.
Vec3 MeshSdf::pseudo_normal(int t, TriangleFeature feature) const {
  const auto& f = triangles()[t];
  const auto& v = vertices();
  switch (feature) {
    case TriangleFeature::Face: return face_normal(t);
    case TriangleFeature::AB:
    case TriangleFeature::BC:
    case TriangleFeature::CA: {
      const int k = static_cast<int>(feature) - static_cast<int>(TriangleFeature::AB);
      const int other = m_neighbour[t][k];
      return (face_normal(t) + (other >= 0 ? face_normal(other) : Vec3::Zero())).normalized();
    }
    default: {
      const int vertex = f[static_cast<int>(feature)];
      Vec3 sum = Vec3::Zero();
      for (int r = m_ring_begin[vertex]; r < m_ring_begin[vertex + 1]; ++r) {
        const auto& g = triangles()[m_ring[r]];
        const int at = g[0] == vertex ? 0 : g[1] == vertex ? 1 : 2;
        const Vec3 e1 = v[g[(at + 1) % 3]] - v[vertex], e2 = v[g[(at + 2) % 3]] - v[vertex];
        sum += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * face_normal(m_ring[r]);
      }
      return sum.normalized();
    }
  }
}

MeshDistance MeshSdf::signed_result(const Vec3& p, const NearestTriangle& nearest) const {
  MeshDistance out;
  if (nearest.triangle < 0) return out;
  const Vec3 pseudo = pseudo_normal(nearest.triangle, nearest.closest.feature);
  const Vec3 d = p - nearest.closest.point;
  const double distance = std::sqrt(nearest.distance_sq);
  const double sign = d.dot(pseudo) < 0 ? -1.0 : 1.0;
  out.phi = sign * distance;
  out.normal = distance > 0 ? Vec3(sign * d / distance) : pseudo;
  out.triangle = nearest.triangle;
  out.bary = nearest.closest.bary;
  return out;
}

MeshDistance MeshSdf::distance(const Vec3& p, double max_distance) const {
  return signed_result(p, m_bvh.nearest(p, max_distance));
}

MeshDistance MeshSdf::distance_brute_force(const Vec3& p, double max_distance) const {
  return signed_result(p, m_bvh.nearest_brute_force(p, max_distance));
}

SdfSample MeshSdf::sdf(const Vec3& p) const {
  const MeshDistance d = distance(p);
  return {d.phi, d.normal};
}

SdfSample MeshSdf::sdf_brute_force(const Vec3& p) const {
  const MeshDistance d = distance_brute_force(p);
  return {d.phi, d.normal};
}

std::shared_ptr<const MeshSdf> load_mesh_obstacle(const ObstacleDesc& ob) {
  TriMesh mesh = read_obj(ob.mesh_path);
  for (Vec3& p : mesh.vertices) p = ob.point + ob.rotation * (ob.scale * p);
  return std::make_shared<const MeshSdf>(mesh);
}

}  // namespace sinew
