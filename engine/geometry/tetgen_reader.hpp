#pragma once
// TetGen mesh reader: a .node file (points) and its .ele file (tetrahedra).
//
//   .node: "<#points> <dimension = 3> <#attributes> <boundary marker 0|1>", then one line
//          per point "<index> <x> <y> <z> [attributes] [marker]".
//   .ele:  "<#tets> <nodes per tet = 4|10> <#attributes>", then one line per tet
//          "<index> <n1> <n2> <n3> <n4> [6 more nodes of a 10-node tet] [attributes]".
// '#' starts a comment; header fields after the first may be omitted (defaults 3, 0, 0 and
// 4, 0). Node numbering is 0- or 1-based, as the first point's index says; the .ele refers
// to nodes in the same numbering. Of a 10-node tet the 4 corners are kept. Attributes and
// markers are read and dropped.
#include <string>

#include "engine/geometry/tet_mesh.hpp"

namespace sinew {

// `path` is the base name ("mesh"), or either file ("mesh.node", "mesh.ele"). Inverted tets
// are reoriented and counted. Throws InputError "FILE:LINE: expected ..." on an unreadable or
// malformed file, a .node without its .ele, a tet referring to a missing node, or a
// degenerate tet.
TetMeshFile read_tetgen(const std::string& path);

}  // namespace sinew
