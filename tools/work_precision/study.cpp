#include "tools/work_precision/study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "tools/work_precision/reference_cache.hpp"

namespace sinew::wp {

namespace {

using Clock = std::chrono::steady_clock;

struct Prepared {
  SceneDesc scene;
  std::string text;  // the scene file, part of every fingerprint
};

Prepared load_variant(const Family& family, const Variant& variant, const StudyOptions& options) {
  const std::string path = options.scenes_dir + "/" + variant.scene_file;
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  Prepared p{load_scene(path), text.str()};
  if (variant.edit) variant.edit(p.scene);
  if (options.quick && family.quick_edit) family.quick_edit(p.scene);
  prepare_for_study(p.scene);
  return p;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

class FamilyRunner {
 public:
  FamilyRunner(const Family& family, const StudyOptions& options) : m_family(family), m_options(options) {
    m_result.name = family.name;
    m_result.description = family.description;
    m_result.violation_kind = family.violation_kind;
    m_result.base_steps = options.quick ? family.quick_steps : family.steps;
    m_result.sample_every = family.sample_every;
    if (options.quick) m_result.quick_note = family.quick_note;
    for (const Variant& v : family.variants)
      if (!v.own_reference) m_result.reference_notes.emplace_back(v.name, v.reference_note);
    for (size_t v = 0; v < family.variants.size(); ++v)
      for (const Sweep& s : family.sweeps)
        if (v == 0 || !s.first_variant_only) m_total += (options.quick ? s.quick_values : s.values).size();
  }

  FamilyResult run() {
    for (size_t v = 0; v < m_family.variants.size(); ++v) run_variant(v);
    return std::move(m_result);
  }

 private:
  // The converged reference of `variant` (h_divisor 16; with 1: the tight tolerances at the
  // scene's own h) on the lattice of `lattice` (a refining sweep and its value, or none: the
  // scene's own lattice), read from the cache or computed and cached.
  const CachedReference& reference(size_t variant, const Sweep* lattice, double value, int h_divisor = 16) {
    Prepared p = load_variant(m_family, m_family.variants[variant], m_options);
    if (lattice) lattice->apply(p.scene, value);
    make_reference(p.scene, h_divisor);
    const int steps = m_result.base_steps * h_divisor, sample_every = m_family.sample_every * h_divisor;
    const nlohmann::json fingerprint = run_fingerprint(p.scene, p.text, steps, sample_every);
    const std::string hash = fingerprint_hash(fingerprint);
    if (auto it = m_references.find(hash); it != m_references.end()) return it->second;

    ReferenceInfo info;
    info.variant = m_family.variants[variant].name;
    info.lattice = lattice ? lattice->label(value) : "c0";
    info.hash = hash;
    info.h_divisor = h_divisor;
    const std::string what = info.variant + " (" + info.lattice + ", " + (h_divisor == 1 ? "h0" : "h0/16");
    std::optional<CachedReference> cached;
    if (!m_options.fresh) cached = load_reference(m_options.cache_dir, fingerprint);
    info.cached = cached.has_value();
    if (!cached) {
      std::fprintf(stderr, "[%s] reference %s, tight tolerances, %d steps)...\n", m_family.name.c_str(), what.c_str(),
                   steps);
      RunResult run = run_scene(p.scene, steps, sample_every);
      cached = CachedReference{std::move(run.samples), run.step_seconds, run.finite, run.steps};
      save_reference(m_options.cache_dir, fingerprint, *cached);
    }
    std::fprintf(stderr, "[%s] reference %s): %s, %.1f s to compute%s\n", m_family.name.c_str(), what.c_str(),
                 info.cached ? "from the cache" : "computed", cached->step_seconds,
                 cached->finite ? "" : ", FAILED before the end (compared up to there)");
    info.finite = cached->finite;
    info.step_seconds = cached->step_seconds;
    info.steps = cached->steps;
    m_result.references.push_back(info);
    return m_references.emplace(hash, std::move(*cached)).first->second;
  }

  void run_variant(size_t v) {
    const Variant& variant = m_family.variants[v];
    const size_t ref_variant = variant.own_reference ? v : 0;
    const CachedReference& own = reference(ref_variant, nullptr, 0);
    const CachedReference* first = v > 0 && variant.own_reference ? &reference(0, nullptr, 0) : nullptr;
    const CachedReference& same_h = reference(ref_variant, nullptr, 0, 1);
    if (first) {
      ReferenceInfo& info = find_reference(variant.name, "c0", 16);
      info.vs_first = compare(own.samples, first->samples);
      info.has_vs_first = true;
    }
    for (const Sweep& sweep : m_family.sweeps) {
      if (v > 0 && sweep.first_variant_only) continue;
      const std::vector<double>& values = m_options.quick ? sweep.quick_values : sweep.values;
      if (values.empty()) continue;
      const CachedReference& ref =
          sweep.refines_lattice ? reference(ref_variant, &sweep, *std::min_element(values.begin(), values.end())) : own;
      for (double value : values) {
        Prepared p = load_variant(m_family, variant, m_options);
        m_result.h0 = p.scene.h;
        m_result.simulated_seconds = m_result.base_steps * p.scene.h;
        sweep.apply(p.scene, value);
        Point point = measure(p);
        point.variant = variant.name;
        point.reference = m_family.variants[ref_variant].name;
        point.sweep = sweep.name;
        point.label = sweep.label(value);
        point.value = value;
        point.errors = compare(point.run.samples, ref.samples);
        if (std::lround(m_result.h0 / point.h) == 1 && !sweep.refines_lattice &&
            (variant.own_reference || variant.same_problem_as_first)) {
          point.solver_errors = compare(point.run.samples, same_h.samples);
          point.has_solver_errors = true;
        }
        if (first && !sweep.refines_lattice) {
          point.errors_vs_first = compare(point.run.samples, first->samples);
          point.has_errors_vs_first = true;
        }
        point.run.samples = {};
        report(point);
        m_result.points.push_back(std::move(point));
      }
    }
  }

  // Runs (or recalls: every sweep holds the scene's own settings once) the point's scene;
  // runs under 1 s are timed 5 times, under 10 s 3 times, and the median kept (the machine
  // is shared: single timings vary by up to a third).
  Point measure(const Prepared& p) {
    const int divisor = std::max(1, static_cast<int>(std::lround(m_result.h0 / p.scene.h)));
    const int steps = m_result.base_steps * divisor, sample_every = m_family.sample_every * divisor;
    const std::string hash = fingerprint_hash(run_fingerprint(p.scene, p.text, steps, sample_every));
    if (auto it = m_points.find(hash); it != m_points.end()) return it->second;
    Point point;
    point.h = p.scene.h;
    point.run = run_scene(p.scene, steps, sample_every);
    std::vector<double> wall = {point.run.step_seconds}, cpu = {point.run.step_cpu_seconds};
    const size_t wanted = point.run.step_seconds < 1 ? 5 : point.run.step_seconds < 10 ? 3 : 1;
    while (point.run.finite && wall.size() < wanted) {
      const RunTimes t = time_scene(p.scene, steps);
      wall.push_back(t.wall);
      cpu.push_back(t.cpu);
    }
    point.repeats = static_cast<int>(wall.size());
    const double simulated = std::max(1, point.run.steps) * p.scene.h;
    point.seconds_per_simulated_second = median(wall) / simulated;
    point.cpu_seconds_per_simulated_second = median(cpu) / simulated;
    m_points.emplace(hash, point);
    return point;
  }

  ReferenceInfo& find_reference(const std::string& variant, const std::string& lattice, int h_divisor) {
    for (ReferenceInfo& r : m_result.references)
      if (r.variant == variant && r.lattice == lattice && r.h_divisor == h_divisor) return r;
    throw std::logic_error("work precision: no reference " + variant);
  }

  void report(const Point& p) {
    ++m_done;
    const double elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
    std::fprintf(stderr, "[%s] %d/%d %s %s=%s: %.3g s per simulated s, RMS %.3g m, max %.3g m%s (%.0f s)\n",
                 m_family.name.c_str(), m_done, m_total, p.variant.c_str(), p.sweep.c_str(), p.label.c_str(),
                 p.seconds_per_simulated_second, p.errors.rms_distance, p.errors.max_distance,
                 p.run.finite ? "" : " FAILED", elapsed);
  }

  const Family& m_family;
  const StudyOptions& m_options;
  FamilyResult m_result;
  std::map<std::string, CachedReference> m_references;  // by fingerprint hash
  std::map<std::string, Point> m_points;                // by fingerprint hash
  int m_total = 0, m_done = 0;
  Clock::time_point m_start = Clock::now();
};

}  // namespace

FamilyResult run_family(const Family& family, const StudyOptions& options) {
  return FamilyRunner(family, options).run();
}

}  // namespace sinew::wp
