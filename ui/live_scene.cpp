#include "ui/live_scene.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/error.hpp"

namespace sinew {
namespace {

// name -> which field; the body's fields are those of the selected body. A template so
// that a const scene gives const pointers.
template <class Scene>
auto field(Scene& scene, int body, const std::string& name) -> decltype(&scene.h) {
  auto& b = scene.bodies[size_t(body)];
  auto& s = scene.solver;
  if (name == "E") return &b.material.E;
  if (name == "nu") return &b.material.nu;
  if (name == "rho") return &b.material.rho;
  if (name == "Umax") return &b.energy_limit.Umax;
  if (name == "h") return &scene.h;
  if (name == "sqp_tolerance") return &s.sqp_tolerance;
  if (name == "strain_tolerance") return &s.strain_tolerance;
  if (name == "newton_tolerance") return &s.newton_tolerance;
  static const char axes[] = "xyz";
  for (int j = 0; j < 3; ++j) {
    if (name == std::string("smin.") + axes[j]) return &b.strain_limit.smin[j];
    if (name == std::string("smax.") + axes[j]) return &b.strain_limit.smax[j];
  }
  return nullptr;
}

template <class Scene>
auto int_field(Scene& scene, const std::string& name) -> decltype(&scene.solver.pgs_max_iterations) {
  if (name == "pgs_max_iterations") return &scene.solver.pgs_max_iterations;
  if (name == "sqp_max_iterations") return &scene.solver.sqp_max_iterations;
  if (name == "newton_max_iterations") return &scene.solver.newton_max_iterations;
  return nullptr;
}

// What a value must satisfy, as the scene file's checks say (docs/scenes.md); empty if fine.
std::string range_error(const std::string& name, double v) {
  if (!std::isfinite(v)) return "a finite number";
  if (name == "nu") return v >= 0 && v < 0.5 ? "" : "a number in [0, 0.5)";
  if (name.rfind("smin.", 0) == 0) return v > 0 && v <= 1 ? "" : "a number in (0, 1]";
  if (name.rfind("smax.", 0) == 0) return v >= 1 ? "" : "a number >= 1";
  if (name.find("max_iterations") != std::string::npos)
    return v >= 1 && v == std::floor(v) && v < 1e7 ? "" : "a whole number >= 1";
  return v > 0 ? "" : "a number > 0";
}

}  // namespace

LiveScene::LiveScene(SceneDesc scene) : m_scene(std::move(scene)) {
  if (m_scene.bodies.empty()) throw InputError(m_scene.name + ": a live scene needs a body");
  rebuild(false);
}

void LiveScene::select_body(const std::string& name) {
  for (size_t b = 0; b < m_scene.bodies.size(); ++b)
    if (m_scene.bodies[b].name == name) {
      m_body = int(b);
      return;
    }
  throw InputError("no body named '" + name + "' in scene '" + m_scene.name + "'");
}

const std::vector<std::string>& LiveScene::parameter_names() {
  static const std::vector<std::string> names = {
      "E", "nu", "rho", "Umax", "smin.x", "smin.y", "smin.z", "smax.x", "smax.y", "smax.z", "h",
      "pgs_max_iterations", "sqp_max_iterations", "newton_max_iterations", "sqp_tolerance",
      "strain_tolerance", "newton_tolerance", "budget_ms"};
  return names;
}

double LiveScene::parameter(const std::string& name) const {
  if (name == "budget_ms") return m_budget_ms;
  if (const double* f = field(m_scene, m_body, name)) return *f;
  if (const int* i = int_field(m_scene, name)) return *i;
  throw InputError("unknown parameter '" + name + "'");
}

void LiveScene::set_parameter(const std::string& name, double value) {
  if (name == "budget_ms") {
    if (!(value >= 0 && value < 1e6))
      throw InputError("parameter 'budget_ms' must be a number >= 0, got " + std::to_string(value));
    m_budget_ms = value;  // a run setting: nothing to rebuild
    return;
  }
  double* f = field(m_scene, m_body, name);
  int* i = int_field(m_scene, name);
  if (!f && !i) throw InputError("unknown parameter '" + name + "'");
  if (const std::string need = range_error(name, value); !need.empty())
    throw InputError("parameter '" + name + "' must be " + need + ", got " + std::to_string(value));
  const BodyDesc& body = m_scene.bodies[size_t(m_body)];
  const bool tet_body = body.elements == "tet" || !body.tet_mesh_path.empty();
  if ((name.rfind("smin.", 0) == 0 || name.rfind("smax.", 0) == 0) && !tet_body)
    throw InputError("parameter '" + name + "': strain limits need a tet body (\"elements\": \"tet\" or a tet_mesh); '" +
                     body.name + "' is made of hexes");
  const SceneDesc before = m_scene;
  if (f) *f = value;
  else *i = int(value);
  if (name == "Umax") m_scene.bodies[size_t(m_body)].energy_limit.enabled = true;
  if (name.rfind("smin.", 0) == 0 || name.rfind("smax.", 0) == 0)
    m_scene.bodies[size_t(m_body)].strain_limit.enabled = true;
  try {
    rebuild(true);
  } catch (const InputError&) {
    m_scene = before;  // e.g. strain limits on a hex body: keep running as before
    throw;
  }
}

void LiveScene::set_material_model(const std::string& model) {
  const auto& names = material_model_names();
  if (std::find(names.begin(), names.end(), model) == names.end())
    throw InputError("unknown material model '" + model + "'");
  if (model != "corotational" && m_scene.bodies[size_t(m_body)].damping_stiffness > 0)
    throw InputError("material model '" + model + "' is hyperelastic: it takes no damping.stiffness (this body has " +
                     std::to_string(m_scene.bodies[size_t(m_body)].damping_stiffness) + " s)");
  const SceneDesc before = m_scene;
  m_scene.bodies[size_t(m_body)].material.model = model;
  try {
    rebuild(true);
  } catch (const InputError&) {
    m_scene = before;
    throw;
  }
}

void LiveScene::set_strain_mode(const std::string& mode) {
  if (mode != "hyperbolic" && mode != "orthogonal" && mode != "linear" && mode != "isotropic")
    throw InputError("strain mode must be hyperbolic, orthogonal, linear or isotropic, got '" + mode + "'");
  m_scene.bodies[size_t(m_body)].strain_limit.mode = mode;
  rebuild(true);
}

void LiveScene::reset() { rebuild(false); }

void LiveScene::rebuild(bool keep_state) {
  auto world = std::make_unique<World>(build_model(m_scene, [](const std::string&) {}),
                                       initial_velocities(m_scene));
  if (keep_state && m_world) {
    const State& old = m_world->state();
    State& now = world->mutable_state();
    now.x = old.x;
    now.v = old.v;
    now.t = old.t;
    now.step_count = old.step_count;
    now.external_force = old.external_force;
    now.surface = old.surface;
  }
  m_world = std::move(world);
}

}  // namespace sinew
