// Orientation and boundary extraction of tet meshes.
#include "engine/geometry/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sinew {

int orient_tets_positively(TetMesh& mesh, std::vector<int>* degenerate) {
  int swapped = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    auto& tet = mesh.tets[t];
    const Vec3& x0 = mesh.nodes[tet[0]];
    const Vec3& x1 = mesh.nodes[tet[1]];
    const Vec3& x2 = mesh.nodes[tet[2]];
    const Vec3& x3 = mesh.nodes[tet[3]];
    const double six_v = 6 * tet_signed_volume(x0, x1, x2, x3);
    double longest2 = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        longest2 = std::max(longest2, (mesh.nodes[tet[a]] - mesh.nodes[tet[b]]).squaredNorm());
    if (std::abs(six_v) <= kDegenerateTet * longest2 * std::sqrt(longest2)) {
      if (degenerate) degenerate->push_back(int(t));
    } else if (six_v < 0) {
      std::swap(tet[2], tet[3]);  // an odd permutation flips the sign of the determinant
      ++swapped;
    }
  }
  return swapped;
}

int count_unreferenced_nodes(const TetMesh& mesh) {
  std::vector<char> used(mesh.nodes.size(), 0);
  for (const auto& tet : mesh.tets)
    for (int n : tet) used[n] = 1;
  return int(std::count(used.begin(), used.end(), 0));
}

TetSurface tet_boundary_surface(const TetMesh& mesh) {
  // Each face is keyed by its sorted node triple; sorting the keys groups the uses of a
  // face together (faster and more deterministic than a hash map).
  struct FaceUse {
    std::array<int, 3> key;
    int tet;
    int face;
  };
  std::vector<FaceUse> uses;
  uses.reserve(mesh.tets.size() * 4);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key;
      for (int i = 0; i < 3; ++i) key[i] = mesh.tets[t][kTetOutwardFaces[f][i]];
      std::sort(key.begin(), key.end());
      uses.push_back({key, int(t), f});
    }
  std::sort(uses.begin(), uses.end(), [](const FaceUse& a, const FaceUse& b) {
    return a.key != b.key ? a.key < b.key : (a.tet != b.tet ? a.tet < b.tet : a.face < b.face);
  });

  TetSurface out;
  std::vector<std::array<int, 3>> faces;  // boundary faces over tet node indices
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 1) {
      std::array<int, 3> face;
      for (int k = 0; k < 3; ++k)
        face[k] = mesh.tets[uses[i].tet][kTetOutwardFaces[uses[i].face][k]];
      faces.push_back(face);
    }
    i = j;
  }

  // Renumber the boundary nodes in increasing node order.
  std::vector<int> vertex_of_node(mesh.nodes.size(), -1);
  for (const auto& f : faces)
    for (int n : f) vertex_of_node[n] = 0;
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    if (vertex_of_node[n] < 0) continue;
    vertex_of_node[n] = int(out.node_of_vertex.size());
    out.node_of_vertex.push_back(int(n));
    out.mesh.vertices.push_back(mesh.nodes[n]);
  }
  out.mesh.triangles.reserve(faces.size());
  for (const auto& f : faces)
    out.mesh.triangles.push_back(
        {vertex_of_node[f[0]], vertex_of_node[f[1]], vertex_of_node[f[2]]});
  return out;
}

}  // namespace sinew
