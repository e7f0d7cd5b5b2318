#pragma once
// Converged references are expensive (h / 16, tight tolerances): each is kept on disk as
// DIR/KEY.bin, KEY a hash of everything that defines it (the scene file's text, the scene
// settings after the study's edits, the run length and sampling, a format version), so that
// editing a scene, a setting or the sampling makes a new one and an unchanged reference is
// read back. Engine changes are not in the key: run with --fresh after one.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "tools/work_precision/run.hpp"

namespace sinew::wp {

// What defines a run: the scene file text plus the SceneDesc settings the study may change.
nlohmann::json run_fingerprint(const SceneDesc& scene, const std::string& scene_text, int steps, int sample_every);

// 16 hex digits of FNV-1a 64 over the fingerprint's compact dump.
std::string fingerprint_hash(const nlohmann::json& fingerprint);

struct CachedReference {
  Trajectory samples;
  double step_seconds = 0;  // what computing it took
  bool finite = true;
  int steps = 0;
};

// Reads DIR/HASH.bin if it exists and was written for exactly this fingerprint.
std::optional<CachedReference> load_reference(const std::string& dir, const nlohmann::json& fingerprint);
// Writes it whole or not at all (engine/io/atomic_file.hpp), creating DIR.
void save_reference(const std::string& dir, const nlohmann::json& fingerprint, const CachedReference& reference);

}  // namespace sinew::wp
