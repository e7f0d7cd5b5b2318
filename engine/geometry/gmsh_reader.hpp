#pragma once
// Gmsh .msh reader, ASCII format versions 2.2 and 4.1.
//
// Reads $MeshFormat, $Nodes and $Elements; every other section ($PhysicalNames, $Entities,
// $NodeData, ...) is skipped. Of the elements only 4-node tetrahedra (element type 4) are
// kept; points, lines, triangles, quads and the rest are ignored. Nodes are kept in file
// order (also those no tet uses: see TetMeshFile::unreferenced_nodes); node tags may be
// sparse, the tets are renumbered to 0-based node indices.
#include <string>

#include "engine/geometry/tet_mesh.hpp"

namespace sinew {

// Inverted tets are reoriented and counted. Throws InputError "FILE:LINE: expected ..." on
// an unreadable or malformed file, a binary file, another format version, a tet referring
// to an unknown node tag, a degenerate tet, or a file without tetrahedra (surface-only).
TetMeshFile read_gmsh(const std::string& path);

}  // namespace sinew
