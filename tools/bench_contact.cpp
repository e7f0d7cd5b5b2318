// sinew_bench_contact: times the collision stage (contact rows: broad phase, distance
// queries, rows) for the armadillo of paper 000 (2 m, ~365 cells, 86k-triangle surface)
// lying on the ground (a plane, or a triangle-mesh slab), and for two armadillos in
// contact, through the broad phase / Embree BVH and through the brute-force path. Medians
// over repeats, JSON out. Skips cleanly when the shared mesh is missing.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <unistd.h>

#include "engine/constraints/body_contact_rows.hpp"
#include "engine/constraints/contact_rows.hpp"
#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/model.hpp"
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

std::string source_dir() { return SINEW_SOURCE_DIR; }

std::string armadillo_path() {
  const std::string mesh = source_dir() + "/../shared/meshes/armadillo.obj";
  if (!std::filesystem::exists(mesh)) throw InputError("armadillo mesh not found at " + mesh);
  return mesh;
}

// A flat ground slab [-2, 2] x [-0.2, 0] x [-2, 2] whose top face is an n x n grid of quads
// (2 n^2 triangles), written as a closed OBJ: a triangle-mesh obstacle to query.
std::string ground_slab_obj(int n) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("sinew_bench_ground_" + std::to_string(::getpid()) + ".obj")).string();
  std::ofstream out(path);
  auto at = [&](int i, int j) { return 1 + i * (n + 1) + j; };  // top grid vertex, 1-based
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) out << "v " << -2 + 4.0 * i / n << " 0 " << -2 + 4.0 * j / n << "\n";
  const int b = (n + 1) * (n + 1);  // bottom corners b+1..b+4
  out << "v -2 -0.2 -2\nv 2 -0.2 -2\nv 2 -0.2 2\nv -2 -0.2 2\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)  // top faces, normal +y: (i,j) (i,j+1) (i+1,j+1)
      out << "f " << at(i, j) << " " << at(i, j + 1) << " " << at(i + 1, j + 1) << "\nf " << at(i, j) << " "
          << at(i + 1, j + 1) << " " << at(i + 1, j) << "\n";
  out << "f " << b + 1 << " " << b + 2 << " " << b + 3 << "\nf " << b + 1 << " " << b + 3 << " " << b + 4 << "\n";
  // Sides: fans from the bottom corners to the top border (each side is a fan, closed).
  auto side = [&](int corner_a, int corner_b, const std::vector<int>& border) {
    for (size_t k = 0; k + 1 < border.size(); ++k) out << "f " << corner_a << " " << border[k + 1] << " " << border[k] << "\n";
    out << "f " << corner_a << " " << corner_b << " " << border.back() << "\n";
  };
  std::vector<int> s0, s1, s2, s3;  // borders z = -2 (j = 0), x = 2 (i = n), z = 2 (j = n), x = -2 (i = 0)
  for (int i = 0; i <= n; ++i) s0.push_back(at(i, 0));
  for (int j = 0; j <= n; ++j) s1.push_back(at(n, j));
  for (int i = n; i >= 0; --i) s2.push_back(at(i, n));
  for (int j = n; j >= 0; --j) s3.push_back(at(0, j));
  side(b + 1, b + 2, s0);
  side(b + 2, b + 3, s1);
  side(b + 3, b + 4, s2);
  side(b + 4, b + 1, s3);
  return path;
}

std::string armadillo_json(const std::string& name) {
  return R"({"name": ")" + name + R"(", "mesh": ")" + armadillo_path() + R"(",
      "transform": {"scale": 2.0}, "cell_size": 0.163, "material": {"E": 5e5, "nu": 0.3, "rho": 500}})";
}

// The armadillo, 2 m tall at cell size 0.163 m (365 cells), its lowest surface vertex on
// y = 0 (on the plane or the slab's top). With `second`, another armadillo beside it,
// shifted along x until the two surfaces interpenetrate by about 1 cm (arms and belly meet).
Model armadillo_on(const std::string& ground_json, bool second = false) {
  std::string bodies = armadillo_json("a");
  if (second) bodies += ", " + armadillo_json("b");
  SceneDesc scene = parse_scene_text(R"({"bodies": [)" + bodies + R"(], "obstacles": [)" + ground_json + "]}",
                                     "bench_contact", source_dir());
  double lowest = 1e300;
  Aabb box;
  {
    const Model probe = build_model(scene, [](const std::string&) {});
    for (const Vec3& p : probe.bodies[0].rest_surface.vertices) lowest = std::min(lowest, p.y()), box.extend(p);
  }
  for (BodyDesc& b : scene.bodies) b.translate.y() -= lowest;
  if (!second) return build_model(scene, [](const std::string&) {});
  // Bisection on the shift: the deepest vertex of b inside a (rest surfaces) is ~1 cm.
  double lo = 0.2 * (box.hi.x() - box.lo.x()), hi = box.hi.x() - box.lo.x();
  for (int it = 0; it < 20; ++it) {
    scene.bodies[1].translate.x() = 0.5 * (lo + hi);
    const Model m = build_model(scene, [](const std::string&) {});
    BodySurfaces surfaces;
    RowTable rows;
    const double deepest = add_body_contact_rows(m, m.rest_x, VecX::Zero(3 * m.num_nodes), {}, surfaces, rows).deepest;
    (deepest > 0.01 ? lo : hi) = 0.5 * (lo + hi);
  }
  scene.bodies[1].translate.x() = hi;
  return build_model(scene, [](const std::string&) {});
}

struct Timing {
  double median_ms = 0;
  int rows = 0, candidates = 0;
};

// Obstacle rows and body-vs-body rows, as the constraint stage builds them per SQP
// iteration (body surfaces refitted each time).
Timing time_rows(const Model& model, ContactSearch search, int repeats) {
  const VecX v = VecX::Zero(3 * model.num_nodes);
  RowTable rows;
  BodySurfaces surfaces;
  std::vector<double> ms;
  ContactRowsResult result;
  const auto build = [&] {
    ContactRowsResult r = add_contact_rows(model, model.h, model.rest_x, v, {}, rows, search);
    const ContactRowsResult b = add_body_contact_rows(model, model.rest_x, v, {}, surfaces, rows, search);
    r.candidates += b.candidates;
    return r;
  };
  build();  // warm-up (builds the body surfaces' BVHs)
  for (int i = 0; i < repeats; ++i) {
    rows.clear();
    const auto start = std::chrono::steady_clock::now();
    result = build();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], rows.size(), result.candidates};
}

nlohmann::json bench_case(const std::string& name, const Model& model, int repeats, int slow_repeats) {
  const Timing fast = time_rows(model, ContactSearch::BroadPhase, repeats);
  int vertices = 0;
  for (const Body& b : model.bodies) vertices += static_cast<int>(b.embedding.cell.size());
  if (slow_repeats == 0) {
    std::printf("%-22s %5d cells %6d surface vertices %6d rows\n", name.c_str(), model.num_elements, vertices, fast.rows);
    std::printf("  broad phase + BVH   median %10.4f ms  (%d vertices tested, %d repeats)\n", fast.median_ms,
                fast.candidates, repeats);
    std::printf("  brute force         skipped (--brute-force-bodies)\n");
    return {{"cells", model.num_elements}, {"surface_vertices", vertices}, {"rows", fast.rows},
            {"broad_phase", {{"median_ms", fast.median_ms}, {"vertices_tested", fast.candidates}, {"repeats", repeats}}},
            {"brute_force", {{"skipped", "about 3 minutes on 2 cores; run with --brute-force-bodies"}}}};
  }
  const Timing slow = time_rows(model, ContactSearch::BruteForce, slow_repeats);
  std::printf("%-22s %5d cells %6d surface vertices %6d rows\n", name.c_str(), model.num_elements, vertices, fast.rows);
  std::printf("  broad phase + BVH   median %10.4f ms  (%d vertices tested, %d repeats)\n", fast.median_ms,
              fast.candidates, repeats);
  std::printf("  brute force         median %10.4f ms  (%d vertices tested, %d repeats)\n", slow.median_ms,
              slow.candidates, slow_repeats);
  if (fast.rows != slow.rows) std::printf("  WARNING: the two paths found different row counts (%d vs %d)\n", fast.rows, slow.rows);
  return {{"cells", model.num_elements}, {"surface_vertices", vertices}, {"rows", fast.rows},
          {"broad_phase", {{"median_ms", fast.median_ms}, {"vertices_tested", fast.candidates}, {"repeats", repeats}}},
          {"brute_force", {{"median_ms", slow.median_ms}, {"vertices_tested", slow.candidates}, {"repeats", slow_repeats}}}};
}

}  // namespace

int main(int argc, char** argv) {
  cli::Options options(
      "sinew_bench_contact [OPTION...]",
      "Times the collision stage (broad phase, distance queries, contact rows) of paper 000's\n"
      "armadillo (../shared/meshes/armadillo.obj): on a plane (cell broad phase vs every vertex),\n"
      "on a triangle-mesh slab (Embree BVH vs every triangle), and two armadillos in contact on a\n"
      "plane (brute force: every vertex against every triangle of the other surface, only with\n"
      "--brute-force-bodies). Medians over repeats; JSON out. Cases without the mesh are skipped.",
      {{"--repeats", "N", "timed repeats per case (default 50; brute force on the plane:\n"
                          "                          max(3, N/10), elsewhere 1)"},
       {"--threads", "T", "worker threads (default: all cores)"},
       {"--grid", "N", "the slab's top face: N x N quads, 2 N^2 triangles (default 64)"},
       {"--brute-force-bodies", "", "also time the two armadillos by brute force (about 3 minutes\n"
                                    "                          on 2 cores)"},
       {"--out", "FILE", "JSON results (default bench_contact.json)"}},
      0);
  std::string out = "bench_contact.json";
  int repeats = 50, threads = 0, grid = 64;  // threads 0: all cores
  bool brute_bodies = false;
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    repeats = options.get_int("--repeats", repeats, 1);
    threads = options.get_int("--threads", threads, 1);
    grid = options.get_int("--grid", grid, 1);
    brute_bodies = options.has("--brute-force-bodies");
    out = options.get("--out", out);
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_contact: %s\n", e.what());
    return 2;
  }
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  nlohmann::json results = {{"threads", threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())},
                            {"cases", nlohmann::json::object()}};
  const auto run = [&](const std::string& name, const std::function<nlohmann::json()>& body) {
    try {
      results["cases"][name] = body();
    } catch (const std::exception& e) {
      std::printf("%-22s skipped: %s\n", name.c_str(), e.what());
      results["cases"][name] = {{"skipped", e.what()}};
    }
  };
  run("armadillo_plane", [&] {
    return bench_case("armadillo_plane", armadillo_on(R"({"type": "plane"})"), repeats, std::max(3, repeats / 10));
  });
  run("armadillo_mesh_ground", [&] {
    const std::string slab = ground_slab_obj(grid);
    const Model model = armadillo_on(R"({"type": "mesh", "mesh": ")" + slab + R"("})");
    std::filesystem::remove(slab);
    nlohmann::json j = bench_case("armadillo_mesh_ground", model, repeats, 1);
    j["ground_triangles"] = 2 * grid * grid + 2 + 4 * (grid + 1);
    return j;
  });
  run("two_armadillos", [&] {
    const Model model = armadillo_on(R"({"type": "plane"})", true);
    return bench_case("two_armadillos", model, repeats, brute_bodies ? 1 : 0);
  });
  write_file_atomically(out, [&](std::ostream& s) { s << results.dump(2) << "\n"; });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
