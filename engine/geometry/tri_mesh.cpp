// Edge-use counting for closedness checks.
#include "engine/geometry/tri_mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace sinew {

int count_open_edges(const TriMesh& mesh) {
  // Sorting undirected edge keys is faster and more deterministic than a hash map.
  std::vector<std::uint64_t> keys;
  keys.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      auto a = static_cast<std::uint32_t>(t[e]);
      auto b = static_cast<std::uint32_t>(t[(e + 1) % 3]);
      if (a > b) std::swap(a, b);
      keys.push_back((std::uint64_t(a) << 32) | b);
    }
  }
  std::sort(keys.begin(), keys.end());
  int open = 0;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i != 2) ++open;
    i = j;
  }
  return open;
}

}  // namespace sinew
