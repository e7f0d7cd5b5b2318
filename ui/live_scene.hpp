#pragma once
// The scene a session or the panel edits while it runs: its description and the World
// built from it. A parameter change rebuilds the Model from the edited description and
// carries the state over (positions, velocities, time, applied forces), so the run goes on
// without a restart: a new E gives new element matrices, new limits give new rows.
#include <memory>
#include <string>
#include <vector>

#include "engine/world.hpp"

namespace sinew {

class LiveScene {
 public:
  explicit LiveScene(SceneDesc scene);

  World& world() { return *m_world; }
  const World& world() const { return *m_world; }
  const SceneDesc& scene() const { return m_scene; }

  // The body whose material and limits the parameters below address.
  int selected_body() const { return m_body; }
  void select_body(const std::string& name);  // InputError if there is no such body

  // Parameters by name (docs/sessions.md lists them): material "E", "nu", "rho"; limits
  // "Umax", "smin.x" ... "smax.z" (strain); solver "h", "pgs_max_iterations",
  // "sqp_max_iterations", "newton_max_iterations", "sqp_tolerance", "strain_tolerance",
  // "newton_tolerance"; the run's "budget_ms" (not part of the scene). Unknown names and values out of range throw InputError.
  static const std::vector<std::string>& parameter_names();
  double parameter(const std::string& name) const;
  void set_parameter(const std::string& name, double value);
  // The selected body's material model (material_model_names()).
  void set_material_model(const std::string& model);
  // The strain-limit projection: "hyperbolic", "orthogonal", "linear" or "isotropic".
  void set_strain_mode(const std::string& mode);

  // The real-time budget per frame, ms ("budget_ms"; 0: none, the scene's caps, deterministic).
  double budget_ms() const { return m_budget_ms; }

  // Back to the scene's initial state, keeping the edited parameters.
  void reset();

 private:
  void rebuild(bool keep_state);
  SceneDesc m_scene;
  int m_body = 0;
  double m_budget_ms = 0;
  std::unique_ptr<World> m_world;
};

}  // namespace sinew
