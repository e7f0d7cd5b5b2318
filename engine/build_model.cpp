#include <cmath>
#include <map>
#include <tuple>

#include "engine/collision/mesh_sdf.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/obj_reader.hpp"
#include "engine/geometry/surface_mesher.hpp"
#include "engine/model.hpp"

namespace sinew {
namespace {

std::string where(const SceneDesc& scene, const std::string& json_path) {
  return (scene.path.empty() ? std::string("scene") : scene.path) + ": " + json_path + ": ";
}

Vec3 transform_point(const BodyDesc& desc, const Vec3& p) {
  return desc.translate + desc.rotate * (desc.scale * p);
}

// Reads the OBJ or meshes the analytic shape, then voxelises it.
void build_geometry(const SceneDesc& scene, const BodyDesc& desc, Body& body,
                    const std::function<void(const std::string&)>& warn) {
  if (desc.mesh_path.empty() && desc.shape.parts.empty())
    throw InputError(where(scene, desc.json_path + ".shape") + "the lattice is empty: expected at least one primitive");
  if (!desc.mesh_path.empty()) {
    body.rest_surface = read_obj(desc.mesh_path);
    for (Vec3& p : body.rest_surface.vertices) p = transform_point(desc, p);
    const int open = count_open_edges(body.rest_surface);
    if (open > 0)
      warn(where(scene, desc.json_path + ".mesh") + "mesh '" + desc.mesh_path + "' is not closed (" +
           std::to_string(open) + " open edges); inside/outside may be wrong");
    body.lattice = voxelize_mesh(body.rest_surface, desc.cell_size);
  } else {
    Shape shape = desc.shape;
    for (Primitive& part : shape.parts) {
      part.center = transform_point(desc, part.center);
      part.rotation = desc.rotate * part.rotation;
      part.size *= desc.scale;
    }
    const double resolution =
        desc.surface_resolution > 0 ? desc.surface_resolution : desc.cell_size / 3;
    body.rest_surface = mesh_shape_surface(shape, resolution);
    body.lattice = voxelize_shape(shape, desc.cell_size, body.rest_surface.vertices);
  }
  if (body.lattice.cells.empty())
    throw InputError(where(scene, desc.json_path + ".cell_size") +
                     "the lattice is empty: no cell of size " + std::to_string(desc.cell_size) +
                     " m overlaps the body; expected a cell size smaller than the body");
  body.embedding = embed_points(body.lattice, body.rest_surface.vertices);
  body.surface_cells = group_surface_by_cell(body.embedding, body.num_elements());
}

double element_energy_limit(const BodyDesc& desc, const Vec3& rest_centre) {
  if (!desc.energy_limit.enabled) return 0;
  double Umax = desc.energy_limit.Umax;
  for (const EnergyLimitRegion& r : desc.energy_limit.regions)
    if (r.region.contains(rest_centre)) Umax = r.Umax;  // the last region that matches wins
  return Umax;
}

}  // namespace

Model build_model(const SceneDesc& scene, const std::function<void(const std::string&)>& warn) {
  Model model;
  model.scene_name = scene.name;
  model.obstacles = scene.obstacles;
  for (ObstacleDesc& ob : model.obstacles)
    if (ob.kind == ObstacleDesc::Kind::Mesh) ob.mesh = load_mesh_obstacle(ob);
  model.solver = scene.solver;
  model.gravity = scene.gravity;
  model.h = scene.h;

  std::map<std::tuple<double, double, double>, int> reference_of;
  std::vector<Vec3> rest;
  for (const BodyDesc& desc : scene.bodies) {
    Body body;
    body.name = desc.name;
    body.material = desc.material;
    body.damping_mass = desc.damping_mass;
    body.damping_stiffness = desc.damping_stiffness;
    body.energy_limit = desc.energy_limit;
    build_geometry(scene, desc, body, warn);
    body.node_offset = model.num_nodes;
    body.element_offset = model.num_elements;

    const auto key = std::make_tuple(desc.cell_size, desc.material.E, desc.material.nu);
    auto [it, inserted] = reference_of.emplace(key, static_cast<int>(model.references.size()));
    if (inserted)
      model.references.push_back(compute_hex8_reference(
          desc.cell_size, IsotropicElasticity::from_young_poisson(desc.material.E, desc.material.nu)));

    // Lumped mass: each cell's rho c^3 split equally over its 8 nodes.
    const double node_share = desc.material.rho * std::pow(body.lattice.cell_size, 3) / 8;
    const int b = static_cast<int>(model.bodies.size());
    for (const Vec3& p : body.lattice.nodes) {
      rest.push_back(p);
      model.node_body.push_back(b);
      bool fixed = false;
      for (const RegionDesc& region : desc.fixed) fixed = fixed || region.contains(p);
      model.free_index.push_back(fixed ? -1 : 0);
    }
    model.node_mass.conservativeResize(model.num_nodes + body.num_nodes());
    model.node_mass.tail(body.num_nodes()).setZero();

    std::vector<std::vector<int>> colors(8);
    for (int c = 0; c < body.num_elements(); ++c) {
      std::array<int, 8> nodes = body.lattice.cells[c];
      Vec3 centre = Vec3::Zero();
      for (int& n : nodes) {
        centre += body.lattice.nodes[n] / 8;
        model.node_mass[model.num_nodes + n] += node_share;
        n += model.num_nodes;
      }
      const int e = model.num_elements + c;
      model.element_nodes.push_back(nodes);
      model.element_body.push_back(b);
      model.element_reference.push_back(it->second);
      model.element_Umax.push_back(element_energy_limit(desc, centre));
      const auto& g = body.lattice.cell_coords[c];
      colors[(g[0] & 1) + 2 * (g[1] & 1) + 4 * (g[2] & 1)].push_back(e);
    }
    model.element_colors.resize(8);
    for (int k = 0; k < 8; ++k)
      model.element_colors[k].insert(model.element_colors[k].end(), colors[k].begin(), colors[k].end());

    model.num_nodes += body.num_nodes();
    model.num_elements += body.num_elements();
    model.bodies.push_back(std::move(body));
  }

  model.rest_x.resize(3 * model.num_nodes);
  for (int n = 0; n < model.num_nodes; ++n) model.rest_x.segment<3>(3 * n) = rest[n];
  for (int& f : model.free_index)
    if (f >= 0) f = model.num_free++;
  model.pattern = build_system_pattern(model.element_nodes, model.free_index, model.num_free);
  return model;
}

}  // namespace sinew
