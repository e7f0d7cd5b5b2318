#include <cmath>

#include "tools/work_precision/report.hpp"

namespace sinew::wp {

namespace {

// JSON has no NaN or infinity: null instead.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json errors_json(const Errors& e) {
  return {{"rms_distance", number(e.rms_distance)}, {"max_distance", number(e.max_distance)},
          {"energy_error", number(e.energy_error)}};
}

nlohmann::json point_json(const Point& p) {
  nlohmann::json violation = nlohmann::json::object(), iterations = nlohmann::json::object();
  for (const auto& [kind, v] : p.run.worst_violation) violation[kind] = number(v);
  for (const auto& [solver, n] : p.run.iterations) iterations[solver] = n;
  nlohmann::json j = {{"variant", p.variant}, {"reference", p.reference}, {"sweep", p.sweep}, {"label", p.label}, {"value", p.value}, {"h", p.h},
                      {"finite", p.run.finite}, {"steps", p.run.steps},
                      {"seconds_per_simulated_second", number(p.seconds_per_simulated_second)},
                      {"cpu_seconds_per_simulated_second", number(p.cpu_seconds_per_simulated_second)},
                      {"timing_repeats", p.repeats}, {"errors", errors_json(p.errors)},
                      {"worst_violation", violation}, {"iterations", iterations},
                      {"steps_at_sqp_cap", p.run.steps_at_sqp_cap}, {"axis_strain_excess", number(p.run.axis_strain_excess)},
                      {"worst_volume_change", number(p.run.worst_volume_change)},
                      {"total_volume_change", number(p.run.total_volume_change)}};
  if (p.has_solver_errors) j["solver_errors"] = errors_json(p.solver_errors);
  if (p.has_errors_vs_first) j["errors_vs_first_variant_reference"] = errors_json(p.errors_vs_first);
  return j;
}

}  // namespace

nlohmann::json to_json(const std::vector<FamilyResult>& families, const RunInfo& info) {
  nlohmann::json out = {{"command", info.command}, {"date", info.date}, {"machine", info.machine},
                        {"mode", info.quick ? "quick" : "full"}, {"threads", info.threads},
                        {"total_seconds", info.total_seconds}, {"families", nlohmann::json::array()}};
  for (const FamilyResult& f : families) {
    nlohmann::json refs = nlohmann::json::array(), points = nlohmann::json::array();
    for (const ReferenceInfo& r : f.references) {
      nlohmann::json j = {{"variant", r.variant}, {"lattice", r.lattice}, {"h_divisor", r.h_divisor},
                          {"cache_key", r.hash}, {"cached", r.cached},
                          {"finite", r.finite}, {"steps", r.steps}, {"step_seconds", r.step_seconds}};
      if (r.has_vs_first) j["vs_first_variant_reference"] = errors_json(r.vs_first);
      refs.push_back(j);
    }
    for (const Point& p : f.points) points.push_back(point_json(p));
    nlohmann::json notes = nlohmann::json::object();
    for (const auto& [variant, note] : f.reference_notes) notes[variant] = note;
    out["families"].push_back({{"name", f.name}, {"description", f.description}, {"h0", f.h0},
                               {"simulated_seconds", f.simulated_seconds}, {"steps_at_h0", f.base_steps},
                               {"sample_every_steps_at_h0", f.sample_every}, {"violation_kind", f.violation_kind},
                               {"quick_note", f.quick_note}, {"reference_notes", notes},
                               {"references", refs}, {"points", points}});
  }
  return out;
}

}  // namespace sinew::wp
