#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include "tools/work_precision/report.hpp"

namespace sinew::wp {

namespace {

std::string num(double v, const char* format = "%.3g") {
  if (!std::isfinite(v)) return "-";
  char s[64];
  std::snprintf(s, sizeof s, format, v);
  return s;
}

double violation(const Point& p, const std::string& kind) {
  const auto it = p.run.worst_violation.find(kind);
  return it == p.run.worst_violation.end() ? 0.0 : it->second;
}

long iterations(const Point& p, const std::string& solver) {
  const auto it = p.run.iterations.find(solver);
  return it == p.run.iterations.end() ? 0 : it->second;
}

const FamilyResult* find(const std::vector<FamilyResult>& families, const std::string& name) {
  for (const FamilyResult& f : families)
    if (f.name == name) return &f;
  return nullptr;
}

// RMS distance to the variant's own converged reference, "-" when it has none.
std::string own_rms(const Point& p) { return p.reference == p.variant ? num(p.errors.rms_distance) : "- (none)"; }

// RMS distance to the converged reference of the family's first variant (`first`).
std::string first_rms(const Point& p, const std::string& first) {
  if (p.has_errors_vs_first) return num(p.errors_vs_first.rms_distance);
  return p.reference == first ? num(p.errors.rms_distance) : "-";
}

std::string solver_rms(const Point& p) { return p.has_solver_errors ? num(p.solver_errors.rms_distance) : "-"; }

std::string time_cell(const Point& p) {
  return num(p.seconds_per_simulated_second) + (p.run.finite ? "" : " (failed at step " + std::to_string(p.run.steps + 1) + ")");
}

// A Markdown table: header cells, then one row per point accepted by `keep`.
void table(std::ostringstream& md, const std::vector<std::string>& header, const FamilyResult& f,
           const std::function<bool(const Point&)>& keep, const std::function<std::vector<std::string>(const Point&)>& row) {
  md << "|";
  for (const std::string& h : header) md << " " << h << " |";
  md << "\n|";
  for (size_t i = 0; i < header.size(); ++i) md << "---|";
  md << "\n";
  for (const Point& p : f.points) {
    if (!keep(p)) continue;
    md << "|";
    for (const std::string& cell : row(p)) md << " " << cell << " |";
    md << "\n";
  }
  md << "\n";
}

void references_table(std::ostringstream& md, const FamilyResult& f, const std::string& first) {
  md << "| reference | lattice | h | steps | computed in (s) | read from the cache | cache key | RMS / max distance to the "
     << first << " reference (m) |\n|---|---|---|---|---|---|---|---|\n";
  for (const ReferenceInfo& r : f.references)
    md << "| " << r.variant << (r.finite ? "" : " (failed before the end)") << " | " << r.lattice << " | "
       << (r.h_divisor == 1 ? std::string("h0") : "h0/" + std::to_string(r.h_divisor)) << " | " << r.steps
       << " | " << num(r.step_seconds, "%.1f") << " | " << (r.cached ? "yes" : "no") << " | `" << r.hash << "` | "
       << (r.has_vs_first ? num(r.vs_first.rms_distance) + " / " + num(r.vs_first.max_distance) : std::string("")) << " |\n";
  md << "\n";
}

void paper000(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "### Paper 000: exact vs warped energy-limit Jacobians\n\n"
        "Both Jacobians linearise the same constraint, so both are measured against the exact-Jacobian "
        "reference. `h` rows at the scene's solver settings, then the PGS cap. (The creature's 100 J limit "
        "first binds at 1.6 s, after its short run: there both Jacobians give the same run.)\n\n";
  for (const char* name : {"paper000_beam"}) {
    const FamilyResult* f = find(families, name);
    if (!f) continue;
    md << "**" << f->description << "**\n\n";
    table(md, {"Jacobian", "setting", "s per simulated s", "RMS (m)", "max (m)", "solver RMS (m)", "worst Ue/Umax - 1",
               "worst penetration (m)",
               "SQP iterations", "steps at SQP cap", "PGS iterations"},
          *f, [](const Point& p) { return p.sweep == "h" || p.sweep == "pgs_max_iterations"; },
          [](const Point& p) {
            return std::vector<std::string>{p.variant, p.sweep == "h" ? p.label : "PGS cap " + p.label, time_cell(p),
                                            num(p.errors.rms_distance), num(p.errors.max_distance), solver_rms(p),
                                            num(violation(p, "energy")), num(violation(p, "penetration")),
                                            std::to_string(iterations(p, "sqp")), std::to_string(p.run.steps_at_sqp_cap),
                                            std::to_string(iterations(p, "pgs"))};
          });
  }
}

void paper001(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "### Paper 001: hyperbolic vs orthogonal vs linear strain-limit projection\n\n"
        "Each projection constrains a different set, so each has its own converged reference; the distance "
        "to the first variant's reference says how far the method's answer is from it. "
        "\"Own violation\" is the solver's measure (the mode's constraints); \"stretch past limit\" is "
        "the same for every mode: the worst |F m_j| of any element beyond smin_j or smax_j of its "
        "material axis m_j (isotropic: the singular values), over the samples.\n\n";
  for (const char* name : {"paper001_vertical", "paper001_beam"}) {
    const FamilyResult* f = find(families, name);
    if (!f) continue;
    const std::string first = f->references.empty() ? "first" : f->references.front().variant;
    md << "**" << f->description << "**\n\n";
    table(md, {"limits", "h", "s per simulated s", "RMS to own reference (m)", "RMS to " + first + " reference (m)",
               "own worst violation", "stretch past limit", "SQP iterations", "steps at SQP cap"},
          *f, [](const Point& p) { return p.sweep == "h"; },
          [&](const Point& p) {
            return std::vector<std::string>{p.variant, p.label, time_cell(p), own_rms(p), first_rms(p, first),
                                            num(violation(p, "strain")), num(p.run.axis_strain_excess),
                                            std::to_string(iterations(p, "sqp")), std::to_string(p.run.steps_at_sqp_cap)};
          });
  }
}

void paper003(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  const FamilyResult* f = find(families, "paper003_elbow");
  if (!f) return;
  md << "### Paper 003: Stable vs classic Neo-Hookean vs corotational\n\n"
        "Three energies, three converged answers (each its own reference). Volume change at the end of the "
        "run (J = det F at element centres; the elbow is bent and held).\n\n**"
     << f->description << "**\n\n";
  table(md, {"material", "h", "s per simulated s", "Newton iterations", "RMS to own reference (m)",
             "RMS to stable_neo_hookean reference (m)", "worst abs(J - 1)", "total volume change"},
        *f, [](const Point& p) { return p.sweep == "h"; },
        [](const Point& p) {
          return std::vector<std::string>{p.variant, p.label, time_cell(p), std::to_string(iterations(p, "newton")),
                                          own_rms(p), first_rms(p, "stable_neo_hookean"),
                                          num(p.run.worst_volume_change), num(p.run.total_volume_change, "%+.3g")};
        });
}

void all_points(std::ostringstream& md, const FamilyResult& f) {
  const std::string first = f.references.empty() ? "first" : f.references.front().variant;
  md << "### " << f.name << "\n\n" << f.description << ". Simulated " << num(f.simulated_seconds) << " s at h0 = "
     << num(f.h0, "%.6g") << " s (" << f.base_steps << " steps), sampled every " << f.sample_every
     << " steps of h0." << (f.quick_note.empty() ? "" : " Quick run: " + f.quick_note + ".") << "\n\n";
  for (const auto& [variant, note] : f.reference_notes)
    md << "- " << variant << " is measured against the " << first << " reference: " << note << ".\n";
  md << (f.reference_notes.empty() ? "" : "\n") << "![" << f.name << "](" << f.name << ".png)\n\n";
  references_table(md, f, first);
  const std::string kind = f.violation_kind;
  table(md, {"variant", "swept", "value", "s per simulated s", "CPU s per simulated s", "timings", "RMS (m)", "max (m)", "solver RMS (m)", "energy error",
             kind.empty() ? "-" : "worst " + kind, "SQP", "PGS", "Newton"},
        f, [](const Point&) { return true; },
        [&](const Point& p) {
          return std::vector<std::string>{p.variant, p.sweep, p.label, time_cell(p),
                                          num(p.cpu_seconds_per_simulated_second), std::to_string(p.repeats),
                                          num(p.errors.rms_distance), num(p.errors.max_distance), solver_rms(p),
                                          num(p.errors.energy_error),
                                          kind.empty() ? "-" : num(violation(p, kind)), std::to_string(iterations(p, "sqp")),
                                          std::to_string(iterations(p, "pgs")), std::to_string(iterations(p, "newton"))};
        });
}

}  // namespace

std::string markdown_summary(const std::vector<FamilyResult>& families, const RunInfo& info) {
  std::ostringstream md;
  md << "## Measured tables\n\n"
     << "Command: `" << info.command << "` (" << (info.quick ? "quick" : "full") << " run, " << info.threads
     << " thread" << (info.threads == 1 ? "" : "s") << "). Date: " << info.date << ". Machine: " << info.machine
     << ". Wall time of the whole run: " << num(info.total_seconds / 60, "%.1f") << " min.\n\n";
  md << "## The papers' comparisons\n\n";
  paper000(md, families);
  paper001(md, families);
  paper003(md, families);
  md << "## Every point, per family\n\n";
  for (const FamilyResult& f : families) all_points(md, f);
  return md.str();
}

}  // namespace sinew::wp
