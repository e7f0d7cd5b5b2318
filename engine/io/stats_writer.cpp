#include "engine/io/stats_writer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>

#include "engine/io/atomic_file.hpp"

namespace sinew {

namespace {

// Stage times summed by name, in first-seen order.
std::vector<std::pair<std::string, double>> stage_totals(const FrameStats& f) {
  std::vector<std::pair<std::string, double>> r;
  for (const auto& [name, ms] : f.stages) {
    auto it = r.begin();
    while (it != r.end() && it->first != name) ++it;
    if (it == r.end()) r.emplace_back(name, ms);
    else it->second += ms;
  }
  return r;
}

bool all_finite(const FrameStats& f) {
  bool ok = f.finite && std::isfinite(f.t) && std::isfinite(f.step_ms) && std::isfinite(f.kinetic_energy);
  for (const auto& s : f.stages) ok = ok && std::isfinite(s.second);
  for (const auto& v : f.violation) ok = ok && std::isfinite(v.second);
  return ok;
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// Shortest round-trip text; to_chars ignores the locale.
void put(std::ostream& out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.write(buf, r.ptr - buf);
}

// RFC 4180 quoting, only when needed.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string r = "\"";
  for (char c : s) r += c == '"' ? std::string("\"\"") : std::string(1, c);
  return r + "\"";
}

}  // namespace

void write_stats_json(const std::string& path, const std::vector<FrameStats>& frames,
                      const nlohmann::json& summary) {
  nlohmann::json doc;
  doc["frames"] = nlohmann::json::array();
  for (const FrameStats& f : frames) {
    nlohmann::json j;
    j["t"] = number(f.t);
    j["step_ms"] = number(f.step_ms);
    j["stages"] = nlohmann::json::object();
    for (const auto& [name, ms] : stage_totals(f)) j["stages"][name] = number(ms);
    j["rows"] = f.rows;
    j["iterations"] = f.iterations;
    j["violation"] = nlohmann::json::object();
    for (const auto& [name, v] : f.violation) j["violation"][name] = number(v);
    j["kinetic_energy"] = number(f.kinetic_energy);
    j["finite"] = all_finite(f);
    j["skipped"] = nlohmann::json::object();
    for (const auto& [stage, reason] : f.skipped) j["skipped"][stage] = reason;
    doc["frames"].push_back(std::move(j));
  }
  doc["summary"] = summary;
  // dump throws on invalid UTF-8 in names; inside the writer that leaves no file.
  write_file_atomically(path, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
}

void write_stats_csv(const std::string& path, const std::vector<FrameStats>& frames) {
  std::vector<std::string> stage_names;
  for (const FrameStats& f : frames)
    for (const auto& s : f.stages)
      if (std::find(stage_names.begin(), stage_names.end(), s.first) == stage_names.end())
        stage_names.push_back(s.first);

  write_file_atomically(path, [&](std::ostream& out) {
    out << "t,step_ms";
    for (const std::string& name : stage_names) out << ',' << csv_field(name);
    out << ",kinetic_energy,finite\n";
    for (const FrameStats& f : frames) {
      put(out, f.t);
      out << ',';
      put(out, f.step_ms);
      const auto totals = stage_totals(f);
      for (const std::string& name : stage_names) {
        out << ',';
        for (const auto& [n, ms] : totals)
          if (n == name) put(out, ms);
      }
      out << ',';
      put(out, f.kinetic_energy);
      out << ',' << (all_finite(f) ? "true" : "false") << '\n';
    }
  });
}

}  // namespace sinew
