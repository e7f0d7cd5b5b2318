// Paper 000, fig. 6 ("falling creature"): a 2 m creature (356 hex of 0.138 m, 500 kg/m^3)
// dropped 0.5 m onto the ground. The paper: the compliant one (500 kPa) collapses, the stiff
// one (5 MPa) barely deforms, the energy-limited one (500 kPa, Ue <= 100 J) avoids extreme
// deformation. Checked here over the scene's 3 s as an ordering, limited between stiff and
// compliant, of the smallest element volume ratio and of the lowest head height after
// landing; the limited creature's largest element energy stays at the cap, the compliant
// one's goes beyond it; the limit and the contacts hold within their solver tolerances.
//
// What happens in this scene (measured): the landing (steps 20-30) is mild for every
// variant: the compliant creature's legs peak at Ue ~81 J, under the 100 J cap, so up to
// step ~90 the limited and compliant runs are identical. The extreme deformation comes
// after: all three tip over backwards onto the tail; the compliant one's tail root bends
// to Ue ~800 J and the creature slumps to the ground, the limited one's tail root holds at
// 100 J, the stiff one rests on its tail almost undeformed. The landing figures are
// printed separately.
//
// Volume bound of the limit (derived in test_paper000_collapse.cpp): an element with
// Ue <= Umax (1 + tol) has det F >= (1 - a/3)^3 at its centre, a = sqrt(Umax (1 + tol) /
// (K c^3)), when 2 mu (1 - a/3) > K a. Here (E 500 kPa, nu 0.3, c 0.138 m, 100 J): >= 0.727.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/analysis/element_fields.hpp"
#include "engine/simulate_frame.hpp"

using namespace sinew;

namespace {

struct CreatureRun {
  double min_volume_ratio = 1;      // det F at element centres, smallest over elements and steps
  double max_energy = 0;            // largest element Ue = u^T Ke u over the run, J
  double landing_min_volume_ratio = 1, landing_max_energy = 0;  // the same over the landing steps
  double head_rest = 0;             // highest head vertex at rest, m
  double head_lowest = 1e300;       // its lowest over the steps after the first contact, m
  double head_end = 0;              // at the end of the run, m
  int first_contact = -1;           // step of the first contact row
  double worst_limit = -1;          // largest Ue/Umax - 1 over limited elements (-1: no limit)
  double worst_energy_violation = 0, worst_penetration = 0;  // FrameStats, max over steps
  double sqp_tolerance = 0, contact_tolerance = 0;
  double Umax = 0, volume_ratio_bound = 0, bound_condition = 0;
};

// `head_above`: the head is the surface vertices higher than this at rest (m).
CreatureRun run_scene(const SceneDesc& scene, double head_above, int frames, int landing_steps) {
  World w(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  const Model& m = w.model();
  const Body& body = m.bodies[0];
  CreatureRun r;
  r.sqp_tolerance = m.solver.sqp_tolerance;
  r.contact_tolerance = m.solver.contact_tolerance;
  r.Umax = m.element_Umax[0];
  if (r.Umax > 0) {
    const double c = body.lattice.cell_size, mu = body.material.E / (2 * (1 + body.material.nu));
    const double K = body.material.E / (3 * (1 - 2 * body.material.nu));
    const double a = std::sqrt(r.Umax * (1 + r.sqp_tolerance) / (K * c * c * c));
    r.volume_ratio_bound = std::pow(1 - a / 3, 3);
    r.bound_condition = 2 * mu * (1 - a / 3) / (K * a);
  }
  std::vector<int> head;
  for (int i = 0; i < static_cast<int>(body.rest_surface.vertices.size()); ++i)
    if (body.rest_surface.vertices[i].y() > head_above) head.push_back(i);
  REQUIRE(head.size() > 10);
  const auto head_height = [&] {
    double y = -1e300;
    for (int i : head) y = std::max(y, w.state().surface[0][i].y());
    return y;
  };
  r.head_rest = head_height();
  const int steps_per_frame = scene.steps_per_frame();
  for (int f = 0; f < frames; ++f) {
    const FrameStats stats = simulate_frame(w, steps_per_frame);
    REQUIRE(stats.finite);
    const int step = (f + 1) * steps_per_frame;
    if (stats.violation.count("energy"))
      r.worst_energy_violation = std::max(r.worst_energy_violation, stats.violation.at("energy"));
    if (stats.violation.count("penetration"))
      r.worst_penetration = std::max(r.worst_penetration, stats.violation.at("penetration"));
    if (r.first_contact < 0 && stats.rows.count("contact")) r.first_contact = step;
    const auto fields = compute_element_fields(m, w.state());
    for (double J : fields.at("volume_ratio")) {
      r.min_volume_ratio = std::min(r.min_volume_ratio, J);
      if (step <= landing_steps) r.landing_min_volume_ratio = std::min(r.landing_min_volume_ratio, J);
    }
    for (int e = 0; e < m.num_elements; ++e) {
      const double Ue = hex8_limit_energy(m.references[m.element_reference[e]],
                                          element_corotated_displacement(m, w.state().x, e));
      r.max_energy = std::max(r.max_energy, Ue);
      if (step <= landing_steps) r.landing_max_energy = std::max(r.landing_max_energy, Ue);
      if (m.element_Umax[e] > 0) r.worst_limit = std::max(r.worst_limit, Ue / m.element_Umax[e] - 1);
    }
    if (r.first_contact >= 0) r.head_lowest = std::min(r.head_lowest, head_height());
  }
  r.head_end = head_height();
  return r;
}

CreatureRun run_creature(const std::string& variant, int frames, int landing_steps) {
  // The head: surface vertices above the top of the body ellipsoid (2.1 m at rest; the arms
  // end below 2.0 m), i.e. the upper part of the head sphere.
  return run_scene(load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_creature_" + variant + ".json"),
                   2.15, frames, landing_steps);
}

}  // namespace

TEST_CASE("paper 000 fig. 6: the energy-limited creature deforms less than the compliant one and more than the stiff one") {
  // The scene's full 3 s (180 steps of 1/60 s): the landing is at step ~20, the tipping
  // over and the compliant creature's slump take until ~2.3 s (step 140).
  const int frames = 180, landing_steps = 45;
  const CreatureRun compliant = run_creature("500kPa", frames, landing_steps);
  const CreatureRun stiff = run_creature("5MPa", frames, landing_steps);
  const CreatureRun limited = run_creature("500kPa_U100", frames, landing_steps);
  for (const auto& [name, r] : {std::pair<std::string, const CreatureRun&>{"500 kPa", compliant}, {"5 MPa", stiff},
                                {"500 kPa, Umax 100 J", limited}}) {
    MESSAGE(name << ": first contact at step " << r.first_contact << "; landing (steps <= " << landing_steps
                 << "): smallest volume ratio " << r.landing_min_volume_ratio << ", largest Ue "
                 << r.landing_max_energy << " J; whole run: smallest volume ratio " << r.min_volume_ratio
                 << ", largest Ue " << r.max_energy << " J, head " << r.head_rest << " m at rest, lowest "
                 << r.head_lowest << " m after landing, " << r.head_end << " m at the end; worst Ue/Umax - 1 "
                 << r.worst_limit << ", worst penetration " << r.worst_penetration << " m");
    REQUIRE(r.first_contact > 0);
    CHECK(r.worst_penetration <= r.contact_tolerance);
  }
  MESSAGE("the 100 J limit allows a volume ratio down to " << limited.volume_ratio_bound << " (bound condition "
                                                           << limited.bound_condition << " > 1)");
  CHECK(limited.bound_condition > 1);  // the bound below is valid

  // The limit holds on every step (solver's measure and ours).
  CHECK(limited.worst_energy_violation <= limited.sqp_tolerance);
  CHECK(limited.worst_limit <= limited.sqp_tolerance);
  // The compliant creature's extreme deformation is beyond what the limit allows, in
  // energy and in volume; the limited one stays within the bound.
  CHECK(compliant.max_energy > limited.Umax * (1 + limited.sqp_tolerance));
  CHECK(compliant.min_volume_ratio < limited.volume_ratio_bound);
  CHECK(limited.min_volume_ratio >= limited.volume_ratio_bound);
  // Ordering: stiff deforms least, limited in between, compliant most.
  CHECK(stiff.min_volume_ratio > limited.min_volume_ratio);
  CHECK(limited.min_volume_ratio > compliant.min_volume_ratio);
  CHECK(stiff.head_lowest > limited.head_lowest);
  CHECK(limited.head_lowest > compliant.head_lowest);
}

TEST_CASE("paper 000 fig. 6 with ../shared/meshes/armadillo.obj: the limit holds and caps what the compliant one exceeds") {
  // assets/scenes/armadillo_creature_500kPa_U100.json: the same scene with the armadillo
  // (2 m tall, 0.163 m cells, 365 hex) in place of the procedural creature; its mesh path
  // points at ../shared from the scene's folder. Here the path is set from the source tree;
  // without the mesh the case says so and checks nothing.
  const std::string mesh = std::string(SINEW_SOURCE_DIR) + "/../shared/meshes/armadillo.obj";
  if (!std::ifstream(mesh)) {
    MESSAGE("skipped: " << mesh << " is absent");
    return;
  }
  const std::string path = std::string(SINEW_SOURCE_DIR) + "/assets/scenes/armadillo_creature_500kPa_U100.json";
  std::ifstream in(path);
  nlohmann::json text = nlohmann::json::parse(in);
  text["bodies"][0]["mesh"] = mesh;
  const SceneDesc limited_scene = parse_scene_text(text.dump(), path, SINEW_SOURCE_DIR);
  SceneDesc compliant_scene = limited_scene;
  compliant_scene.bodies[0].energy_limit.enabled = false;
  // The head: within 0.3 m of the top of the armadillo at rest (its top at about 2.55 m).
  double top = -1e300;
  {
    const Model probe = build_model(limited_scene, [](const std::string&) {});
    for (const Vec3& p : probe.bodies[0].rest_surface.vertices) top = std::max(top, p.y());
  }
  const int frames = 180, landing_steps = 45;
  const CreatureRun limited = run_scene(limited_scene, top - 0.3, frames, landing_steps);
  const CreatureRun compliant = run_scene(compliant_scene, top - 0.3, frames, landing_steps);
  for (const auto& [name, r] : {std::pair<std::string, const CreatureRun&>{"armadillo 500 kPa", compliant},
                                {"armadillo 500 kPa, Umax 100 J", limited}}) {
    MESSAGE(name << ": first contact at step " << r.first_contact << "; smallest volume ratio " << r.min_volume_ratio
                 << ", largest Ue " << r.max_energy << " J, head lowest " << r.head_lowest << " m after landing; worst "
                 << "Ue/Umax - 1 " << r.worst_limit << ", worst penetration " << r.worst_penetration << " m");
    REQUIRE(r.first_contact > 0);
    CHECK(r.worst_penetration <= r.contact_tolerance);
  }
  CHECK(limited.worst_energy_violation <= limited.sqp_tolerance);
  CHECK(limited.worst_limit <= limited.sqp_tolerance);
  CHECK(compliant.max_energy > limited.Umax * (1 + limited.sqp_tolerance));
  CHECK(limited.min_volume_ratio > compliant.min_volume_ratio);
}
