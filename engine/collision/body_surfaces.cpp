#include "engine/collision/body_surfaces.hpp"

#include "engine/model.hpp"

namespace sinew {

const MeshSdf& deformed_surface(const Model& model, int b, const VecX& x, BodySurfaces& surfaces) {
  const Body& body = model.bodies[b];
  surfaces.mesh.resize(model.bodies.size());
  compute_embedded_positions(body.embedding, body.lattice, x, body.node_offset, surfaces.scratch);
  if (!surfaces.mesh[b]) {
    TriMesh mesh{surfaces.scratch, body.rest_surface.triangles};
    surfaces.mesh[b] = std::make_shared<MeshSdf>(mesh, true);
  } else {
    surfaces.mesh[b]->update(surfaces.scratch);
  }
  return *surfaces.mesh[b];
}

}  // namespace sinew
