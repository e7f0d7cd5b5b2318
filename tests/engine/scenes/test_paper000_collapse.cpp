// Paper 000, fig. 5 ("collapsing sphere"): a compliant sphere (R 1 m, 117 hex of 0.45 m,
// 500 kg/m^3, E 50 kPa) released 2 cm above the ground collapses under its own weight;
// with an energy limit (Ue <= 50 J per element) it keeps its volume. Checked here as: the
// limited sphere's worst element volume loss stays within what the limit allows (a bound
// derived below), the compliant sphere's exceeds that bound, and both the worst element
// loss and the total volume loss of the limited sphere are less than half the compliant
// one's; the limit and the contacts hold within their solver tolerances on every step.
//
// The bound. Ue = sum over the 8 Gauss points of w sigma:eps (Ke is 2x2x2 Gauss-integrated,
// sum of w = c^3). The trilinear element's strain at the centre is the mean of its Gauss
// point strains, so by convexity c^3 sigma(eps_c):eps_c <= Ue <= Umax (1 + sqp_tolerance).
// Write eps_c = -a/3 I + d (d deviatoric): sigma:eps = K a^2 + 2 mu |d|^2. The volume ratio
// at the centre is det F = det(R^T F) = det(I + eps_c + omega) >= det(I + eps_c) (omega skew,
// I + eps_c positive definite), and over this energy ellipsoid det(I + eps_c) is smallest at
// hydrostatic compression when 2 mu (1 - a/3) > K a (spending energy on d lowers a faster
// than d lowers the product; checked below): J >= (1 - a/3)^3 with a = sqrt(Umax (1 + tol) /
// (K c^3)). For E 50 kPa, nu 0.3, c 0.45 m, Umax 50 J: a = 0.115, J >= 0.889, so no element
// may lose more than 11 % of its volume.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/analysis/element_fields.hpp"
#include "engine/simulate_frame.hpp"

using namespace sinew;

namespace {

struct CollapseRun {
  double worst_element_loss = 0;  // 1 - smallest det F at an element centre, over elements and steps
  double worst_total_loss = 0;    // 1 - smallest (sum_e det F_e c^3) / (n c^3) over steps
  double max_energy = 0;          // largest element Ue = u^T Ke u over the run, J
  double worst_limit = -1;        // largest Ue/Umax - 1 over limited elements (-1: no limit)
  double worst_energy_violation = 0, worst_penetration = 0;  // FrameStats, max over steps
  double top_rest = 0, top_lowest = 1e300;  // highest surface vertex at rest / its lowest over the run, m
  double sqp_tolerance = 0, contact_tolerance = 0;
  double volume_ratio_bound = 0;  // smallest det F the energy limit allows (0 without a limit)
  double bound_condition = 0;     // 2 mu (1 - a/3) / (K a): > 1 for the bound to hold
};

double top_of(const World& w) {
  double top = -1e300;
  for (const Vec3& p : w.state().surface[0]) top = std::max(top, p.y());
  return top;
}

CollapseRun run_collapse(const std::string& variant, int frames) {
  const SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_collapse_" + variant + ".json");
  World w(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  const Model& m = w.model();
  CollapseRun r;
  r.sqp_tolerance = m.solver.sqp_tolerance;
  r.contact_tolerance = m.solver.contact_tolerance;
  r.top_rest = top_of(w);
  const double c = m.bodies[0].lattice.cell_size;
  if (m.element_Umax[0] > 0) {
    const MaterialDesc& mat = m.bodies[0].material;
    const double mu = mat.E / (2 * (1 + mat.nu));
    const double K = mat.E / (3 * (1 - 2 * mat.nu));
    const double a = std::sqrt(m.element_Umax[0] * (1 + r.sqp_tolerance) / (K * c * c * c));
    r.volume_ratio_bound = std::pow(1 - a / 3, 3);
    r.bound_condition = 2 * mu * (1 - a / 3) / (K * a);
  }
  for (int f = 0; f < frames; ++f) {
    const FrameStats stats = simulate_frame(w, scene.steps_per_frame());
    REQUIRE(stats.finite);
    if (stats.violation.count("energy"))
      r.worst_energy_violation = std::max(r.worst_energy_violation, stats.violation.at("energy"));
    if (stats.violation.count("penetration"))
      r.worst_penetration = std::max(r.worst_penetration, stats.violation.at("penetration"));
    const auto fields = compute_element_fields(m, w.state());
    double volume = 0;
    for (double J : fields.at("volume_ratio")) {
      r.worst_element_loss = std::max(r.worst_element_loss, 1 - J);
      volume += J;
    }
    r.worst_total_loss = std::max(r.worst_total_loss, 1 - volume / m.num_elements);
    for (int e = 0; e < m.num_elements; ++e) {
      const double Ue = hex8_limit_energy(m.references[m.element_reference[e]],
                                          element_corotated_displacement(m, w.state().x, e));
      r.max_energy = std::max(r.max_energy, Ue);
      if (m.element_Umax[e] > 0) r.worst_limit = std::max(r.worst_limit, Ue / m.element_Umax[e] - 1);
    }
    r.top_lowest = std::min(r.top_lowest, top_of(w));
  }
  return r;
}

}  // namespace

TEST_CASE("paper 000 fig. 5: the energy-limited sphere keeps its volume, the compliant one collapses") {
  // 1 s: the compliant sphere is at its deepest collapse at 0.55-0.6 s and has sprung back
  // by 1.1 s; the limited one settles by 0.25 s.
  const int frames = 60;
  const CollapseRun compliant = run_collapse("50kPa", frames);
  const CollapseRun limited = run_collapse("50kPa_U50", frames);
  for (const auto& [name, r] : {std::pair<std::string, const CollapseRun&>{"50 kPa", compliant}, {"50 kPa, Umax 50 J", limited}}) {
    MESSAGE(name << ": worst element volume loss " << 1e2 * r.worst_element_loss << " %, worst total volume loss "
                 << 1e2 * r.worst_total_loss << " %, top of the sphere " << r.top_rest << " m down to "
                 << r.top_lowest << " m, largest Ue " << r.max_energy << " J, worst Ue/Umax - 1 " << r.worst_limit
                 << ", worst penetration " << r.worst_penetration << " m (tolerance " << r.contact_tolerance << ")");
  }
  MESSAGE("the limit allows a volume ratio down to " << limited.volume_ratio_bound << " (a loss of "
                                                     << 1e2 * (1 - limited.volume_ratio_bound)
                                                     << " %); bound condition " << limited.bound_condition << " > 1");
  CHECK(limited.bound_condition > 1);  // the bound below is valid

  // The limit holds on every step within the SQP tolerance (solver's own measure and ours).
  CHECK(limited.worst_energy_violation <= limited.sqp_tolerance);
  CHECK(limited.worst_limit <= limited.sqp_tolerance);
  // ... hence no element loses more volume than the bound allows,
  CHECK(limited.worst_element_loss <= 1 - limited.volume_ratio_bound);
  // while the compliant sphere's elements go well past it: its collapse is large.
  CHECK(compliant.worst_element_loss > 1 - limited.volume_ratio_bound);
  // Clearly smaller: less than half the compliant sphere's loss, per element and in total.
  // Both runs share the lattice, the drop and the contact; without the limit doing the work
  // the two losses would be equal (ratio 1), so a factor 2 separates the claim from
  // solver-level differences (measured: 61 % vs 7.8 % per element, 11.3 % vs 2.3 % in total).
  CHECK(limited.worst_element_loss < 0.5 * compliant.worst_element_loss);
  CHECK(limited.worst_total_loss < 0.5 * compliant.worst_total_loss);
  // Contacts hold within the contact tolerance on every step.
  CHECK(limited.worst_penetration <= limited.contact_tolerance);
  CHECK(compliant.worst_penetration <= compliant.contact_tolerance);
}
