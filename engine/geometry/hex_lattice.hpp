#pragma once
// A regular hexahedral lattice: the simulation mesh of a hex body.
//
// Node order inside a cell follows paper 000, section 3.2: node n (0-based) has natural
// coordinates s = (2a-1, 2b-1, 2c-1) where n = 4a + 2b + c, a, b, c in {0, 1}; s1 is along
// world x, s2 along y, s3 along z (lattice axes are world axes at rest).
#include "engine/core/types.hpp"
#include "engine/geometry/shape.hpp"
#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

struct HexLattice {
  double cell_size = 0;
  Vec3 origin = Vec3::Zero();                 // world position of grid point (0, 0, 0)
  std::vector<Vec3> nodes;                    // rest positions, unique, shared by cells
  std::vector<std::array<int, 8>> cells;      // node indices, paper order
  std::vector<std::array<int, 3>> cell_coords;  // integer grid coordinates of each cell
};

// Keeps the cells that overlap the solid; the exact rule is documented in voxelize.cpp and
// docs/scenes.md. Every point of the shape's surface lies in a kept cell.
HexLattice voxelize_shape(const Shape& shape, double cell_size);

// As above, and also keeps every cell that holds one of `must_cover` (e.g. the vertices of
// mesh_shape_surface, which sit a little off the exact surface), so all of them embed.
HexLattice voxelize_shape(const Shape& shape, double cell_size, const std::vector<Vec3>& must_cover);

// Keeps every cell whose centre is inside the closed surface (ray parity along x) and
// every cell that holds a surface vertex, so that the whole surface can be embedded.
HexLattice voxelize_mesh(const TriMesh& mesh, double cell_size);

// Lattice of a grid-aligned box: nx*ny*nz cells starting at `origin`.
HexLattice make_box_lattice(const Vec3& origin, double cell_size, int nx, int ny, int nz);

// Integer coordinates c of the grid cell [origin + h c, origin + h (c + 1)) that holds p.
// Voxelization and embedding share it so that a point lands in the cell kept for it.
std::array<int, 3> grid_cell_of(const Vec3& origin, double cell_size, const Vec3& p);

}  // namespace sinew
