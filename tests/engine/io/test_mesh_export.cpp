#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "engine/io/mesh_export.hpp"

namespace fs = std::filesystem;
using sinew::Vec3;

namespace {

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sinew_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Text between the opening DataArray tag carrying `attr` and its closing tag.
std::string data_array(const std::string& xml, const std::string& attr) {
  const size_t tag = xml.find(attr);
  REQUIRE(tag != std::string::npos);
  const size_t begin = xml.find('>', tag) + 1;
  const size_t end = xml.find("</DataArray>", begin);
  REQUIRE(end != std::string::npos);
  return xml.substr(begin, end - begin);
}

template <class T>
std::vector<T> numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<T> r;
  for (T v; in >> v;) r.push_back(v);
  return r;
}

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \n");
  return b == std::string::npos ? "" : s.substr(b, s.find_last_not_of(" \n") - b + 1);
}

// Unit cube corner of paper node n = 4a + 2b + c.
Vec3 paper_corner(int n) { return Vec3((n >> 2) & 1, (n >> 1) & 1, n & 1); }

}  // namespace

TEST_CASE("io: write_obj round trip") {
  const fs::path d = fresh_dir("obj");
  sinew::TriMesh mesh;
  mesh.vertices = {Vec3(0.1, -2.5e-7, 123456.789), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1.0 / 3.0)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const fs::path path = d / "m.obj";
  sinew::write_obj(path.string(), mesh);

  std::istringstream in(slurp(path));
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string kind;
    ls >> kind;
    if (kind == "v") {
      Vec3 p;
      ls >> p[0] >> p[1] >> p[2];
      REQUIRE(!ls.fail());
      v.push_back(p);
    } else if (kind == "f") {
      std::array<int, 3> t;
      ls >> t[0] >> t[1] >> t[2];
      REQUIRE(!ls.fail());
      f.push_back({t[0] - 1, t[1] - 1, t[2] - 1});
    } else {
      FAIL("unexpected line: " << line);
    }
  }
  REQUIRE(v.size() == mesh.vertices.size());
  REQUIRE(f == mesh.triangles);
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k)
      CHECK(v[i][k] == doctest::Approx(mesh.vertices[i][k]).epsilon(1e-8));
  CHECK(v[0][2] == 123456.789);  // 9 significant digits keep this exactly
  fs::remove_all(d);
}

TEST_CASE("io: write_vtu reorders a paper-order cell to VTK_HEXAHEDRON order") {
  const fs::path d = fresh_dir("vtu_order");
  std::vector<Vec3> points;
  for (int n = 0; n < 8; ++n) points.push_back(paper_corner(n));
  const fs::path path = d / "cube.vtu";
  sinew::write_vtu(path.string(), points, {{0, 1, 2, 3, 4, 5, 6, 7}}, {{"stress", {2.5}}, {"j", {1.0}}});
  const std::string xml = slurp(path);

  // Bottom face counter-clockwise from +z, then the face above it.
  CHECK(trim(data_array(xml, "Name=\"connectivity\"")) == "0 4 6 2 1 5 7 3");
  CHECK(trim(data_array(xml, "Name=\"offsets\"")) == "8");
  CHECK(trim(data_array(xml, "Name=\"types\"")) == "12");
  CHECK(numbers<double>(data_array(xml, "Name=\"stress\"")) == std::vector<double>{2.5});
  CHECK(numbers<double>(data_array(xml, "Name=\"j\"")) == std::vector<double>{1.0});
  CHECK(xml.find("NumberOfPoints=\"8\" NumberOfCells=\"1\"") != std::string::npos);
  const std::vector<double> xyz = numbers<double>(data_array(xml, "NumberOfComponents=\"3\""));
  REQUIRE(xyz.size() == 24);
  for (int n = 0; n < 8; ++n)
    CHECK(Vec3(xyz[3 * n], xyz[3 * n + 1], xyz[3 * n + 2]) == points[n]);
  fs::remove_all(d);
}

TEST_CASE("io: write_vtu corners land where VTK expects them, for shuffled node storage") {
  const fs::path d = fresh_dir("vtu_geom");
  // Two cells side by side along x; node storage order unrelated to corner order.
  std::vector<Vec3> points;
  std::array<int, 8> c0{}, c1{};
  const std::array<int, 12> storage = {7, 3, 11, 0, 5, 9, 1, 10, 2, 6, 4, 8};  // grid id -> point index
  points.resize(12);
  for (int gx = 0; gx < 3; ++gx)
    for (int gy = 0; gy < 2; ++gy)
      for (int gz = 0; gz < 2; ++gz) points[storage[gx * 4 + gy * 2 + gz]] = Vec3(gx, gy, gz) * 0.5;
  for (int n = 0; n < 8; ++n) {
    const int a = (n >> 2) & 1, b = (n >> 1) & 1, c = n & 1;
    c0[n] = storage[a * 4 + b * 2 + c];
    c1[n] = storage[(a + 1) * 4 + b * 2 + c];
  }
  const fs::path path = d / "two.vtu";
  sinew::write_vtu(path.string(), points, {c0, c1}, {});
  const std::string xml = slurp(path);
  const std::vector<int> conn = numbers<int>(data_array(xml, "Name=\"connectivity\""));
  REQUIRE(conn.size() == 16);
  CHECK(numbers<int>(data_array(xml, "Name=\"offsets\"")) == std::vector<int>{8, 16});
  const int vtk_bits[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int cell = 0; cell < 2; ++cell) {
    const Vec3 lo = points[conn[8 * cell]];
    for (int k = 0; k < 8; ++k) {
      const Vec3 expected = lo + 0.5 * Vec3(vtk_bits[k][0], vtk_bits[k][1], vtk_bits[k][2]);
      CHECK(points[conn[8 * cell + k]] == expected);
    }
  }
  fs::remove_all(d);
}

TEST_CASE("io: exports reject bad input and write nothing") {
  const fs::path d = fresh_dir("export_reject");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Vec3> points;
  for (int n = 0; n < 8; ++n) points.push_back(paper_corner(n));
  const std::vector<std::array<int, 8>> cells = {{0, 1, 2, 3, 4, 5, 6, 7}};
  const std::string vtu = (d / "bad.vtu").string();

  SUBCASE("non-finite point") {
    points[5].y() = inf;
    CHECK_THROWS_AS(sinew::write_vtu(vtu, points, cells, {}), std::runtime_error);
  }
  SUBCASE("non-finite field") {
    CHECK_THROWS_AS(sinew::write_vtu(vtu, points, cells, {{"f", {nan}}}), std::runtime_error);
  }
  SUBCASE("field of wrong size") {
    CHECK_THROWS_AS(sinew::write_vtu(vtu, points, cells, {{"f", {1.0, 2.0}}}), std::runtime_error);
  }
  SUBCASE("node index out of range") {
    CHECK_THROWS_AS(sinew::write_vtu(vtu, points, {{0, 1, 2, 3, 4, 5, 6, 8}}, {}), std::runtime_error);
  }
  SUBCASE("non-finite obj vertex") {
    sinew::TriMesh mesh;
    mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, nan, 0)};
    mesh.triangles = {{0, 1, 2}};
    CHECK_THROWS_AS(sinew::write_obj((d / "bad.obj").string(), mesh), std::runtime_error);
  }
  CHECK(fs::is_empty(d));
  fs::remove_all(d);
}

TEST_CASE("io: PvdCollection lists every added frame in order") {
  const fs::path d = fresh_dir("pvd");
  sinew::PvdCollection pvd(d.string(), "run");
  pvd.add(0.0, "frame_0000.vtu");
  const fs::path path = d / "run.pvd";
  REQUIRE(fs::exists(path));
  CHECK(slurp(path).find("file=\"frame_0000.vtu\"") != std::string::npos);
  pvd.add(0.25, "frame_0001.vtu");
  CHECK_THROWS_AS(pvd.add(std::numeric_limits<double>::quiet_NaN(), "frame_x.vtu"), std::runtime_error);

  const std::string xml = slurp(path);
  CHECK(xml.find("type=\"Collection\"") != std::string::npos);
  const size_t first = xml.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frame_0000.vtu\"/>");
  const size_t second = xml.find("<DataSet timestep=\"0.25\" group=\"\" part=\"0\" file=\"frame_0001.vtu\"/>");
  CHECK(first != std::string::npos);
  CHECK(second != std::string::npos);
  CHECK(first < second);
  CHECK(xml.find("frame_x") == std::string::npos);
  int datasets = 0;
  for (size_t p = xml.find("<DataSet"); p != std::string::npos; p = xml.find("<DataSet", p + 1)) ++datasets;
  CHECK(datasets == 2);
  CHECK(std::distance(fs::directory_iterator(d), fs::directory_iterator()) == 1);  // no temp left
  fs::remove_all(d);
}
