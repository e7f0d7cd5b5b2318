#pragma once
// Wavefront OBJ reader: `v` and `f` records only (polygons are fan-triangulated; texture
// and normal indices, negative indices and other records are accepted and ignored).
#include <string>

#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

// Throws InputError "PATH:LINE: what was expected" on unreadable files, malformed
// numbers, out-of-range indices, or a file with no triangles.
TriMesh read_obj(const std::string& path);

}  // namespace sinew
