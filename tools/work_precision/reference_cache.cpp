#include "tools/work_precision/reference_cache.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>

#include "engine/io/atomic_file.hpp"

namespace sinew::wp {

namespace {

// Bump when the file layout or the meaning of a sample changes.
constexpr uint32_t kFormatVersion = 9;  // 2: sqp_stall_tolerance in the fingerprint; 3: sqp_acceleration; 4: sqp_solves;
                                        // 5: newton_predictor; 6: divergence_violation_limit; 7: sqp_cap_extension;
                                        // 8: sqp_restoration; 9: sqp_kkt_stop
constexpr char kMagic[8] = {'S', 'W', 'P', 'R', 'E', 'F', '\n', '\0'};

nlohmann::json vec3(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

template <class T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}
template <class T>
bool get(std::istream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

std::string path_of(const std::string& dir, const nlohmann::json& fingerprint) {
  return dir + "/" + fingerprint_hash(fingerprint) + ".bin";
}

}  // namespace

nlohmann::json run_fingerprint(const SceneDesc& scene, const std::string& scene_text, int steps, int sample_every) {
  const SolverDesc& s = scene.solver;
  nlohmann::json solver = {
      {"linear", s.linear}, {"pcg_tolerance", s.pcg_tolerance}, {"pcg_max_iterations", s.pcg_max_iterations},
      {"pgs_max_iterations", s.pgs_max_iterations}, {"pgs_tolerance", s.pgs_tolerance},
      {"pgs_subspace_interval", s.pgs_subspace_interval}, {"pgs_sweeps", s.pgs_sweeps},
      {"sqp_max_iterations", s.sqp_max_iterations}, {"sqp_tolerance", s.sqp_tolerance},
      {"sqp_position_tolerance", s.sqp_position_tolerance},
      {"sqp_stall_tolerance", s.sqp_stall_tolerance}, {"sqp_cap_extension", s.sqp_cap_extension},
      {"sqp_restoration", s.sqp_restoration}, {"sqp_kkt_stop", s.sqp_kkt_stop},
      {"sqp_acceleration", s.sqp_acceleration}, {"sqp_solves", s.sqp_solves},
      {"newton_predictor", s.newton_predictor},
      {"refactor_interval", s.refactor_interval}, {"curved_refactor_interval", s.curved_refactor_interval},
      {"stale_factor_precision", s.stale_factor_precision}, {"hessian_reuse_tolerance", s.hessian_reuse_tolerance},
      {"delassus_reuse", s.delassus_reuse},
      {"activation_margin", s.activation_margin}, {"contact_tolerance", s.contact_tolerance},
      {"contact_margin", s.contact_margin}, {"body_friction", s.body_friction}, {"max_speed", s.max_speed},
      {"divergence_violation_limit", s.divergence_violation_limit},
      {"strain_tolerance", s.strain_tolerance}, {"strain_activation_margin", s.strain_activation_margin},
      {"newton_max_iterations", s.newton_max_iterations}, {"newton_tolerance", s.newton_tolerance},
      {"sleep_steps", s.sleep_steps}};
  nlohmann::json bodies = nlohmann::json::array();
  for (const BodyDesc& b : scene.bodies) {
    nlohmann::json umax = nlohmann::json::array();
    for (const EnergyLimitRegion& r : b.energy_limit.regions) umax.push_back(r.Umax);
    bodies.push_back({{"cell_size", b.cell_size}, {"surface_resolution", b.surface_resolution}, {"elements", b.elements},
                      {"model", b.material.model}, {"E", b.material.E}, {"nu", b.material.nu}, {"rho", b.material.rho},
                      {"damping", {b.damping_mass, b.damping_stiffness}},
                      {"energy_limit", {b.energy_limit.enabled, b.energy_limit.Umax, b.energy_limit.jacobian, umax}},
                      {"strain_limit", {b.strain_limit.enabled, vec3(b.strain_limit.smin), vec3(b.strain_limit.smax), b.strain_limit.mode}}});
  }
  return {{"format", kFormatVersion}, {"scene_text", scene_text}, {"h", scene.h}, {"gravity", vec3(scene.gravity)},
          {"solver", solver}, {"bodies", bodies}, {"steps", steps}, {"sample_every", sample_every}};
}

std::string fingerprint_hash(const nlohmann::json& fingerprint) {
  uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : fingerprint.dump()) hash = (hash ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return hex;
}

// Layout: magic, version, the fingerprint's dump (length-prefixed; checked on read, so a
// hash collision cannot return the wrong reference), finite, steps, step_seconds, then
// samples and vertices counts, times, energies and positions (doubles, native order).
std::optional<CachedReference> load_reference(const std::string& dir, const nlohmann::json& fingerprint) {
  std::ifstream in(path_of(dir, fingerprint), std::ios::binary);
  if (!in) return std::nullopt;
  char magic[8];
  uint32_t version = 0;
  uint64_t key_size = 0;
  if (!in.read(magic, 8) || !std::equal(magic, magic + 8, kMagic) || !get(in, version) || version != kFormatVersion ||
      !get(in, key_size) || key_size > (1u << 30))
    return std::nullopt;
  std::string key(key_size, '\0');
  if (!in.read(key.data(), key_size) || key != fingerprint.dump()) return std::nullopt;
  CachedReference r;
  uint8_t finite = 0;
  uint64_t samples = 0, vertices = 0;
  if (!get(in, finite) || !get(in, r.steps) || !get(in, r.step_seconds) || !get(in, samples) || !get(in, vertices) ||
      samples > (1u << 24) || vertices > (1u << 26))
    return std::nullopt;
  r.finite = finite != 0;
  r.samples.times.resize(samples);
  r.samples.energy.resize(samples);
  r.samples.surface.assign(samples, std::vector<Vec3>(vertices));
  for (double& t : r.samples.times)
    if (!get(in, t)) return std::nullopt;
  for (double& e : r.samples.energy)
    if (!get(in, e)) return std::nullopt;
  for (std::vector<Vec3>& surface : r.samples.surface)
    if (!in.read(reinterpret_cast<char*>(surface.data()), static_cast<std::streamsize>(vertices * sizeof(Vec3))))
      return std::nullopt;
  return r;
}

void save_reference(const std::string& dir, const nlohmann::json& fingerprint, const CachedReference& r) {
  ensure_directory(dir);
  const std::string key = fingerprint.dump();
  const Trajectory& t = r.samples;
  const uint64_t vertices = t.surface.empty() ? 0 : t.surface.front().size();
  for (const std::vector<Vec3>& surface : t.surface)
    if (surface.size() != vertices) throw std::runtime_error("work precision: surface vertex count changed during a run");
  write_file_atomically(path_of(dir, fingerprint), [&](std::ostream& out) {
    out.write(kMagic, 8);
    put(out, kFormatVersion);
    put(out, static_cast<uint64_t>(key.size()));
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    put(out, static_cast<uint8_t>(r.finite));
    put(out, r.steps);
    put(out, r.step_seconds);
    put(out, static_cast<uint64_t>(t.times.size()));
    put(out, vertices);
    for (double time : t.times) put(out, time);
    for (double e : t.energy) put(out, e);
    for (const std::vector<Vec3>& surface : t.surface)
      out.write(reinterpret_cast<const char*>(surface.data()), static_cast<std::streamsize>(vertices * sizeof(Vec3)));
  });
}

}  // namespace sinew::wp
