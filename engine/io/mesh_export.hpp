#pragma once
// Per-frame exports: embedded surface as OBJ, lattice as VTK XML unstructured grid with
// per-cell fields, and a ParaView .pvd collection indexing the .vtu files by time.
#include <map>
#include <string>

#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

void write_obj(const std::string& path, const TriMesh& mesh);

// Hexahedra (VTK_HEXAHEDRON = 12) in paper order, reordered to VTK's; cells with -1 in slots
// 4-7 are tetrahedra (VTK_TETRA = 10).
// Throws if any position or field value is not finite (nothing is written then).
void write_vtu(const std::string& path, const std::vector<Vec3>& points,
               const std::vector<std::array<int, 8>>& cells,
               const std::map<std::string, std::vector<double>>& cell_fields);

// Collects (time, file) pairs and rewrites DIR/NAME.pvd after each add.
class PvdCollection {
 public:
  PvdCollection(std::string directory, std::string name);
  void add(double time, const std::string& vtu_file_name);  // file name relative to directory
 private:
  std::string m_directory, m_name;
  std::vector<std::pair<double, std::string>> m_entries;
};

}  // namespace sinew
