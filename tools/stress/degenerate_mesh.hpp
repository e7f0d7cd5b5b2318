#pragma once
// Case degenerate_mesh: tet mesh files with bad elements, written to a temporary folder.
// A 0.3 m cube of 2 x 2 x 2 cells split into 48 tets, plus one of:
//   flat     a fifth-face tet on 4 coplanar nodes (TetGen and Gmsh): must be an InputError;
//   inverted one tet written with negative orientation (TetGen and Gmsh);
//   folded   the centre node moved out through the top face, so the tets around it are
//            inverted in place and overlap their neighbours;
//   sliver   an extra tet of 6 V = 1e-6 L^3 (above the readers' 1e-12 threshold).
// For the last three, either an InputError or an accepted mesh (the readers reorient) whose
// runs stay finite passes: a corotational and a Stable Neo-Hookean drop onto the ground, 1 s.
// Which one happened is recorded.
#include <stdlib.h>

#include <filesystem>
#include <fstream>

#include "engine/core/error.hpp"
#include "engine/geometry/gmsh_reader.hpp"
#include "engine/geometry/tetgen_reader.hpp"
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

namespace degenerate {

constexpr double kSpacing = 0.15;  // m, grid cell

// 3 x 3 x 3 grid nodes; each cell split along its main diagonal into 6 tets (Kuhn),
// every tet positively oriented.
inline TetMesh cube_mesh() {
  TetMesh mesh;
  auto id = [](int i, int j, int k) { return i + 3 * j + 9 * k; };
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) mesh.nodes.push_back(kSpacing * Vec3(i, j, k));
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        for (const auto& order : axes) {
          std::array<int, 4> tet;
          int c[3] = {i, j, k};
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) ++c[order[s]], tet[s + 1] = id(c[0], c[1], c[2]);
          const auto& X = mesh.nodes;
          if (tet_signed_volume(X[tet[0]], X[tet[1]], X[tet[2]], X[tet[3]]) < 0) std::swap(tet[2], tet[3]);
          mesh.tets.push_back(tet);
        }
  return mesh;
}

inline double signed_volume(const TetMesh& m, const std::array<int, 4>& t) {
  return tet_signed_volume(m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]], m.nodes[t[3]]);
}

struct BadMesh {
  std::string name;
  TetMesh mesh;
  bool must_reject;  // a flat tet has no orientation: only an InputError is right
};

inline std::vector<BadMesh> bad_meshes() {
  std::vector<BadMesh> out;
  TetMesh flat = cube_mesh();
  flat.tets.push_back({0, 2, 8, 6});  // the four corners of the bottom face (z = 0)
  out.push_back({"flat", flat, true});
  TetMesh inverted = cube_mesh();
  std::swap(inverted.tets[20][2], inverted.tets[20][3]);
  out.push_back({"inverted", inverted, false});
  TetMesh folded = cube_mesh();
  folded.nodes[13] = kSpacing * Vec3(1, 1, 2.5);  // the centre node, 0.5 cells above the top face
  out.push_back({"folded", folded, false});
  TetMesh sliver = cube_mesh();
  // Under the bottom face, on the triangle of nodes 0, 1, 3 (legs L = 0.15 m): a height of
  // 1e-6 L over an area of L^2 / 2 gives 6 V = 1e-6 L^3.
  sliver.nodes.push_back(kSpacing * Vec3(0.3, 0.3, -1e-6));
  sliver.tets.push_back({0, 3, 1, 27});
  if (signed_volume(sliver, sliver.tets.back()) < 0) std::swap(sliver.tets.back()[2], sliver.tets.back()[3]);
  out.push_back({"sliver", sliver, false});
  return out;
}

inline int count_inverted(const TetMesh& m) {
  int n = 0;
  for (const auto& t : m.tets) n += signed_volume(m, t) < 0;
  return n;
}

// TetGen .node / .ele, 0-based; returns the .node path.
inline std::string write_tetgen(const TetMesh& m, const std::string& base) {
  std::ofstream node(base + ".node"), ele(base + ".ele");
  node.precision(17);
  node << m.nodes.size() << " 3 0 0\n";
  for (size_t i = 0; i < m.nodes.size(); ++i)
    node << i << " " << m.nodes[i].x() << " " << m.nodes[i].y() << " " << m.nodes[i].z() << "\n";
  ele << m.tets.size() << " 4 0\n";
  for (size_t t = 0; t < m.tets.size(); ++t)
    ele << t << " " << m.tets[t][0] << " " << m.tets[t][1] << " " << m.tets[t][2] << " " << m.tets[t][3] << "\n";
  return base + ".node";
}

// Gmsh ASCII 2.2, 1-based node tags, tets of element type 4 with 2 tags.
inline std::string write_gmsh(const TetMesh& m, const std::string& base) {
  std::ofstream f(base + ".msh");
  f.precision(17);
  f << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m.nodes.size() << "\n";
  for (size_t i = 0; i < m.nodes.size(); ++i)
    f << i + 1 << " " << m.nodes[i].x() << " " << m.nodes[i].y() << " " << m.nodes[i].z() << "\n";
  f << "$EndNodes\n$Elements\n" << m.tets.size() << "\n";
  for (size_t t = 0; t < m.tets.size(); ++t)
    f << t + 1 << " 4 2 0 1 " << m.tets[t][0] + 1 << " " << m.tets[t][1] + 1 << " " << m.tets[t][2] + 1 << " "
      << m.tets[t][3] + 1 << "\n";
  f << "$EndElements\n";
  return base + ".msh";
}

inline std::string drop_scene(const std::string& path, const char* model) {
  return format(R"({"bodies": [{"name": "mesh", "tet_mesh": "%s", "transform": {"translate": [0, 0.1, 0]},
      "material": {"model": "%s", "E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"mass": 1}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})",
                path.c_str(), model);
}

// A folder of our own under the system's temporary folder, removed when done.
struct TempDir {
  std::string path;
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "sinew_stress_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder");
    path = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

}  // namespace degenerate

inline CaseResult run_degenerate_mesh(const Options&) {
  using namespace degenerate;
  const TempDir dir;
  CaseResult r;
  r.details["files"] = nlohmann::json::array();
  int handled = 0, files = 0;
  std::string rejected, accepted;
  for (const BadMesh& bad : bad_meshes()) {
    for (const char* format_name : {"tetgen", "gmsh"}) {
      const bool gmsh = std::string(format_name) == "gmsh";
      if (gmsh && bad.name != "flat" && bad.name != "inverted") continue;  // the readers share the checks
      const std::string base = dir.path + "/" + bad.name;
      const std::string path = gmsh ? write_gmsh(bad.mesh, base) : write_tetgen(bad.mesh, base);
      const std::string label = bad.name + " (" + format_name + ")";
      nlohmann::json entry = {{"file", label}, {"tets_inverted_in_file", count_inverted(bad.mesh)}};
      std::string outcome;
      bool ok = false;
      try {
        const TetMeshFile read = gmsh ? read_gmsh(path) : read_tetgen(path);
        entry["accepted"] = true;
        entry["reoriented"] = read.reoriented;
        bool finite = true;
        for (const char* model : {"corotational", "stable_neo_hookean"}) {
          World world = world_from_text(drop_scene(path, model), label);
          const RunOutcome run = run_steps(world, 60);
          entry[model] = to_json(run);
          finite = finite && run.completed();
          outcome += format("; %s %s", model, describe(run).c_str());
        }
        ok = finite && !bad.must_reject;
        outcome = format("accepted, %d tets reoriented", read.reoriented) + outcome;
      } catch (const InputError& e) {
        ok = true;
        entry["accepted"] = false;
        entry["input_error"] = e.what();
        outcome = std::string("InputError: ") + e.what();
      }
      entry["ok"] = ok;
      r.details["files"].push_back(entry);
      ++files;
      handled += ok;
      std::printf("  %-20s %s%s\n", label.c_str(), ok ? "" : "FAIL: ", outcome.c_str());
      std::fflush(stdout);
      if (entry["accepted"].get<bool>())
        accepted += format("%s%s %d%s", accepted.empty() ? "" : ", ", label.c_str(), entry["reoriented"].get<int>(),
                           ok ? "" : " FAILED");
      else
        rejected += format("%s%s", rejected.empty() ? "" : ", ", label.c_str());
    }
  }
  r.pass = handled == files;
  r.summary = format("%d/%d bad mesh files handled; InputError: ", handled, files) +
              (rejected.empty() ? "none" : rejected) +
              "; accepted (tets reoriented), corotational and Stable Neo-Hookean runs finite: " +
              (accepted.empty() ? "none" : accepted);
  return r;
}

}  // namespace sinew::stress
