#include <algorithm>
#include <cmath>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <map>
#include <numbers>
#include <tuple>

#include "engine/assembly/element_kernels.hpp"
#include "engine/collision/mesh_sdf.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/gmsh_reader.hpp"
#include "engine/geometry/lattice_tets.hpp"
#include "engine/geometry/obj_reader.hpp"
#include "engine/geometry/tetgen_reader.hpp"
#include "engine/materials/invariant_material.hpp"
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
}

// Barycentric weights of p in the tet (a, b, c, d).
std::array<double, 4> barycentric(const std::array<Vec3, 4>& X, const Vec3& p) {
  Mat3 D;
  D << X[1] - X[0], X[2] - X[0], X[3] - X[0];
  const Vec3 l = D.inverse() * (p - X[0]);
  return {1 - l.sum(), l[0], l[1], l[2]};
}

// Stores tets in the body's mesh (slots 4-7 = -1) and a length scale for contact margins.
void store_tets(const TetMesh& mesh, Body& body, double cell_size) {
  body.element_type = ElementType::Tet4;
  body.lattice.nodes = mesh.nodes;
  body.lattice.cells.clear();
  body.lattice.cell_coords.clear();
  double edge_sum = 0;
  for (const auto& t : mesh.tets) {
    body.lattice.cells.push_back({t[0], t[1], t[2], t[3], -1, -1, -1, -1});
    edge_sum += (mesh.nodes[t[1]] - mesh.nodes[t[0]]).norm();
  }
  body.lattice.cell_size = cell_size > 0 ? cell_size : edge_sum / std::max<size_t>(1, mesh.tets.size());
}

// A tet-mesh file: the boundary faces are the surface, each vertex carried by one node.
void build_tet_mesh_geometry(const SceneDesc& scene, const BodyDesc& desc, Body& body) {
  TetMesh mesh;
  try {
    const std::string& path = desc.tet_mesh_path;
    mesh = (path.size() > 4 && path.substr(path.size() - 4) == ".msh" ? read_gmsh(path) : read_tetgen(path)).mesh;
  } catch (const InputError& e) {
    throw InputError(where(scene, desc.json_path + ".tet_mesh") + e.what());
  }
  for (Vec3& p : mesh.nodes) p = transform_point(desc, p);
  store_tets(mesh, body, 0);
  const TetSurface boundary = tet_boundary_surface(mesh);
  body.rest_surface = boundary.mesh;
  std::vector<int> tet_of_node(mesh.nodes.size(), -1), slot_of_node(mesh.nodes.size(), -1);
  for (int t = static_cast<int>(mesh.tets.size()) - 1; t >= 0; --t)
    for (int k = 0; k < 4; ++k) tet_of_node[mesh.tets[t][k]] = t, slot_of_node[mesh.tets[t][k]] = k;
  for (size_t i = 0; i < boundary.mesh.vertices.size(); ++i) {
    const int node = boundary.node_of_vertex[i];
    std::array<double, 8> w{};
    w[slot_of_node[node]] = 1;
    body.embedding.cell.push_back(tet_of_node[node]);
    body.embedding.weights.push_back(w);
  }
}

// A voxel lattice split into tets; the embedded surface moves to barycentric weights in
// the tet of its hex cell that holds it (or is nearest to holding it).
void split_into_tets(Body& body) {
  const LatticeTets split = split_lattice_into_tets(body.lattice);
  std::vector<std::vector<int>> tets_of_cell(body.lattice.cells.size());
  for (size_t t = 0; t < split.tet_cell.size(); ++t) tets_of_cell[split.tet_cell[t]].push_back(static_cast<int>(t));
  Embedding embedding;
  for (size_t i = 0; i < body.rest_surface.vertices.size(); ++i) {
    const Vec3& p = body.rest_surface.vertices[i];
    int best = -1;
    std::array<double, 4> best_w{};
    for (int t : tets_of_cell[body.embedding.cell[i]]) {
      const auto& tet = split.mesh.tets[t];
      const auto w = barycentric({split.mesh.nodes[tet[0]], split.mesh.nodes[tet[1]], split.mesh.nodes[tet[2]],
                                  split.mesh.nodes[tet[3]]}, p);
      if (best < 0 || *std::min_element(w.begin(), w.end()) > *std::min_element(best_w.begin(), best_w.end()))
        best = t, best_w = w;
    }
    std::array<double, 8> w{};
    std::copy(best_w.begin(), best_w.end(), w.begin());
    embedding.cell.push_back(best);
    embedding.weights.push_back(w);
  }
  store_tets(split.mesh, body, body.lattice.cell_size);
  body.embedding = std::move(embedding);
}

std::shared_ptr<const Material> hyperelastic_material(const MaterialDesc& m) {
  if (!m.hyperelastic()) return nullptr;
  MaterialParameters params;
  params.young = m.E;
  params.poisson = m.nu;
  params.fung_c = m.fung_c;
  params.arruda_boyce_n = m.arruda_boyce_n;
  return make_material(m.model == "corotational_hyperelastic" ? "corotational" : m.model, params);
}

double element_energy_limit(const BodyDesc& desc, const Vec3& rest_centre) {
  if (!desc.energy_limit.enabled) return 0;
  double Umax = desc.energy_limit.Umax;
  for (const EnergyLimitRegion& r : desc.energy_limit.regions)
    if (r.region.contains(rest_centre)) Umax = r.Umax;  // the last region that matches wins
  return Umax;
}

}  // namespace

Vec3 DrivenNodes::position(const Vec3& rest, double t) const {
  const double u = duration > 0 ? std::clamp(t / duration, 0.0, 1.0) : 1.0;
  const double angle = radians * u * u * (3 - 2 * u);
  return pivot + Eigen::AngleAxisd(angle, axis) * (rest - pivot);
}

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
    body.strain_limit = desc.strain_limit;
    body.hyperelastic = hyperelastic_material(desc.material);
    if (desc.material.mean_dilatation && !dynamic_cast<const InvariantMaterial*>(body.hyperelastic.get()))
      throw InputError(where(scene, desc.json_path + ".material.volume_term") + "\"mean_dilatation\" needs a model of the form "
                       "f(Ic) + g(J), not \"" + desc.material.model + "\"");
    if (!desc.tet_mesh_path.empty()) {
      build_tet_mesh_geometry(scene, desc, body);
    } else {
      build_geometry(scene, desc, body, warn);
      if (desc.elements == "tet") split_into_tets(body);
    }
    body.surface_cells = group_surface_by_cell(body.embedding, body.num_elements());
    const IsotropicElasticity elasticity = IsotropicElasticity::from_young_poisson(desc.material.E, desc.material.nu);
    body.node_offset = model.num_nodes;
    body.element_offset = model.num_elements;

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

    int reference = -1;
    if (body.element_type == ElementType::Hex8) {
      const auto key = std::make_tuple(desc.cell_size, desc.material.E, desc.material.nu);
      auto [it, inserted] = reference_of.emplace(key, static_cast<int>(model.references.size()));
      if (inserted) model.references.push_back(compute_hex8_reference(desc.cell_size, elasticity));
      reference = it->second;
    }
    for (int c = 0; c < body.num_elements(); ++c) {
      std::array<int, 8> nodes = body.lattice.cells[c];
      const int count = body.element_type == ElementType::Hex8 ? 8 : 4;
      std::array<Vec3, 4> X;
      Vec3 centre = Vec3::Zero();
      for (int a = 0; a < count; ++a) {
        centre += body.lattice.nodes[nodes[a]] / count;
        if (a < 4) X[a] = body.lattice.nodes[nodes[a]];
      }
      // Lumped mass: the element's rho V split equally over its nodes.
      double volume = std::pow(body.lattice.cell_size, 3);
      if (body.element_type == ElementType::Tet4) {
        try {
          model.tet_references.push_back(compute_tet4_reference(X, elasticity));
        } catch (const std::invalid_argument& e) {
          throw InputError(where(scene, desc.json_path) + "element " + std::to_string(c) + " is degenerate: " + e.what());
        }
        Mat83 padded = Mat83::Zero();
        padded.topRows<4>() = model.tet_references.back().dN_dX;
        model.tet_gradients.push_back(padded);
        model.tet_volumes.push_back(model.tet_references.back().volume);
        volume = model.tet_references.back().volume;
        reference = static_cast<int>(model.tet_references.size()) - 1;
      }
      for (int a = 0; a < count; ++a) {
        model.node_mass[model.num_nodes + nodes[a]] += desc.material.rho * volume / count;
        nodes[a] += model.num_nodes;
      }
      model.element_nodes.push_back(nodes);
      model.element_type.push_back(body.element_type);
      model.element_body.push_back(b);
      model.element_reference.push_back(reference);
      model.element_Umax.push_back(element_energy_limit(desc, centre));
      Mat3 frame = desc.strain_limit.frame;
      for (const auto& [region, region_frame] : desc.strain_limit.frame_regions)
        if (region.contains(centre)) frame = region_frame;  // the last region that matches wins
      model.element_strain_frame.push_back(frame);
    }
    // Colours: the lattice's 8 parity classes for hexes, greedy for tets.
    std::vector<std::vector<int>> colors(8);
    if (body.element_type == ElementType::Hex8) {
      for (int c = 0; c < body.num_elements(); ++c) {
        const auto& g = body.lattice.cell_coords[c];
        colors[(g[0] & 1) + 2 * (g[1] & 1) + 4 * (g[2] & 1)].push_back(model.num_elements + c);
      }
    } else {
      // Greedy, element by element in index order: the schedule's colouring with blocks of one.
      const ElementSchedule single = schedule_elements(model.element_nodes, model.num_nodes + body.num_nodes(),
                                                       {{model.num_elements, model.num_elements + body.num_elements()}}, 1);
      colors.assign(single.colors.size(), {});
      for (size_t k = 0; k < single.colors.size(); ++k)
        for (const ElementBlock& block : single.colors[k]) colors[k].push_back(block.first);
    }
    if (model.element_colors.size() < colors.size()) model.element_colors.resize(colors.size());
    for (size_t k = 0; k < colors.size(); ++k)
      model.element_colors[k].insert(model.element_colors[k].end(), colors[k].begin(), colors[k].end());
    for (size_t l = 0; l < desc.loads.size(); ++l) {
      NodeLoad load;
      load.ramp_time = desc.loads[l].ramp_time;
      for (int n = 0; n < body.num_nodes(); ++n)
        if (desc.loads[l].region.contains(body.lattice.nodes[n])) load.nodes.push_back(model.num_nodes + n);
      if (load.nodes.empty())
        throw InputError(where(scene, desc.json_path + ".loads[" + std::to_string(l) + "]") +
                         "the region holds no node of the body; expected a region that overlaps it");
      load.node_force = desc.loads[l].force / static_cast<double>(load.nodes.size());
      model.loads.push_back(load);
    }
    // Driven nodes: not unknowns (free_index -1, like fixed nodes); a node may belong to one
    // driven region and must not be fixed.
    std::vector<int> driven_by(body.num_nodes(), -1);
    for (size_t d = 0; d < desc.driven.size(); ++d) {
      const DrivenDesc& dd = desc.driven[d];
      const std::string path = desc.json_path + ".driven[" + std::to_string(d) + "]";
      DrivenNodes driven;
      driven.axis = dd.axis;
      driven.pivot = dd.pivot;
      driven.radians = dd.degrees * std::numbers::pi / 180;
      driven.duration = dd.duration;
      for (int n = 0; n < body.num_nodes(); ++n) {
        if (!dd.region.contains(body.lattice.nodes[n])) continue;
        if (model.free_index[model.num_nodes + n] < 0 && driven_by[n] < 0)
          throw InputError(where(scene, path) + "node " + std::to_string(n) +
                           " is also in a 'fixed' region; expected driven and fixed regions that do not overlap");
        if (driven_by[n] >= 0)
          throw InputError(where(scene, path) + "node " + std::to_string(n) + " is also in driven[" +
                           std::to_string(driven_by[n]) + "]; expected driven regions that do not overlap");
        driven_by[n] = static_cast<int>(d);
        model.free_index[model.num_nodes + n] = -1;
        driven.nodes.push_back(model.num_nodes + n);
      }
      if (driven.nodes.empty())
        throw InputError(where(scene, path) + "the region holds no node of the body; expected a region that overlaps it");
      model.driven.push_back(std::move(driven));
    }
    model.has_hyperelastic = model.has_hyperelastic || body.hyperelastic;
    model.has_strain_limits = model.has_strain_limits || body.strain_limit.enabled;

    model.num_nodes += body.num_nodes();
    model.num_elements += body.num_elements();
    model.bodies.push_back(std::move(body));
  }

  // Every element on one body's nodes: the system matrix then couples no two bodies, which
  // the constraint solve relies on (Delassus::build_direct leaves rows on no common body out).
  for (int e = 0; e < model.num_elements; ++e)
    for (int a = 0; a < (model.element_type[e] == ElementType::Hex8 ? 8 : 4); ++a)
      if (model.node_body[model.element_nodes[e][a]] != model.element_body[e])
        throw std::logic_error("build_model: an element spans two bodies");
  model.rest_x.resize(3 * model.num_nodes);
  for (int n = 0; n < model.num_nodes; ++n) model.rest_x.segment<3>(3 * n) = rest[n];
  for (int& f : model.free_index)
    if (f >= 0) f = model.num_free++;
  for (Body& body : model.bodies) {
    const double stiffness =
        body.hyperelastic ? [&] {
          const LameParameters lame = lame_parameters({body.material.E, body.material.nu});
          return 2 * lame.mu + lame.lambda;
        }()
                          : 0.0;
    for (int e = body.element_offset; e < body.element_offset + body.num_elements(); ++e) {
      const double volume = element_rest_volume(model, e);
      body.rest_volume += volume;
      body.unit_strain_forces2 += std::pow(stiffness * std::cbrt(volume * volume), 2);
    }
  }
  update_unit_strain_forces(model);
  std::vector<std::pair<int, int>> body_elements;
  for (const Body& body : model.bodies) body_elements.emplace_back(body.element_offset, body.element_offset + body.num_elements());
  model.element_schedule = schedule_elements(model.element_nodes, model.num_nodes, body_elements);
  model.pattern = build_system_pattern(model.element_nodes, model.free_index, model.num_free);
  model.node_elements = build_node_elements(model.element_nodes, model.num_nodes);
  return model;
}

}  // namespace sinew
