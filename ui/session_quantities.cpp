#include "ui/session_quantities.hpp"

#include <limits>

#include "engine/core/error.hpp"

namespace sinew {
namespace {

std::string after(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0 ? s.substr(prefix.size()) : std::string();
}

int axis(const std::string& name) {
  if (name == "x") return 0;
  if (name == "y") return 1;
  if (name == "z") return 2;
  return -1;
}

// body.NAME.min.AXIS, body.NAME.max.AXIS, body.NAME.centroid.AXIS over its surface vertices.
std::optional<double> body_quantity(const std::string& rest, const SessionSnapshot& s) {
  const size_t dot2 = rest.rfind('.');
  if (dot2 == std::string::npos || dot2 == 0) return std::nullopt;
  const size_t dot1 = rest.rfind('.', dot2 - 1);
  if (dot1 == std::string::npos) return std::nullopt;
  const std::string name = rest.substr(0, dot1), what = rest.substr(dot1 + 1, dot2 - dot1 - 1);
  const int a = axis(rest.substr(dot2 + 1));
  const Model& model = s.live.world().model();
  const State& state = s.live.world().state();
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].name != name || a < 0 || b >= state.surface.size()) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
    for (const Vec3& p : state.surface[b]) {
      lo = std::min(lo, p[a]);
      hi = std::max(hi, p[a]);
      sum += p[a];
    }
    if (what == "min") return lo;
    if (what == "max") return hi;
    if (what == "centroid") return sum / double(std::max<size_t>(1, state.surface[b].size()));
  }
  return std::nullopt;
}

}  // namespace

double session_quantity(const std::string& q, const SessionSnapshot& s, const std::string& what) {
  if (const std::string kind = after(q, "violation."); !kind.empty()) {
    static const char* kinds[] = {"energy", "strain", "penetration", "attachment", "newton_residual"};
    for (const char* k : kinds)
      if (kind == k) return s.frame.violation.count(kind) ? s.frame.violation.at(kind) : 0.0;
  } else if (const std::string kind = after(q, "rows."); !kind.empty()) {
    return s.frame.rows.count(kind) ? s.frame.rows.at(kind) : 0;
  } else if (const std::string solver = after(q, "iterations."); !solver.empty()) {
    return s.frame.iterations.count(solver) ? s.frame.iterations.at(solver) : 0;
  } else if (const std::string name = after(q, "parameter."); !name.empty()) {
    return s.live.parameter(name);
  } else if (const std::string rest = after(q, "body."); !rest.empty()) {
    if (const auto v = body_quantity(rest, s)) return *v;
  } else if (const std::string name = after(q, "model."); !name.empty()) {
    // What the engine was built with (the selected body), as opposed to parameter.NAME,
    // the edited description.
    const MaterialDesc& m = s.live.world().model().bodies[size_t(s.live.selected_body())].material;
    if (name == "E") return m.E;
    if (name == "nu") return m.nu;
    if (name == "rho") return m.rho;
  } else if (q == "kinetic_energy") {
    return s.live.world().kinetic_energy();
  } else if (q == "t") {
    return s.live.world().state().t;
  } else if (q == "grab.distance") {
    if (!s.grab) throw InputError(what + ": 'grab.distance' needs a grab (nothing is grabbed)");
    return (attached_point(s.live.world().model(), *s.grab, s.live.world().state().x) - s.grab->target).norm();
  }
  throw InputError(what + ": unknown quantity '" + q +
                   "' (expected violation.KIND, rows.KIND, iterations.SOLVER, parameter.NAME, model.E|nu|rho, "
                   "body.NAME.min|max|centroid.x|y|z, kinetic_energy, t or grab.distance)");
}

}  // namespace sinew
