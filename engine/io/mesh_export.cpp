#include "engine/io/mesh_export.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "engine/io/atomic_file.hpp"

namespace sinew {

namespace {

// Shortest round-trip text when digits == 0, else that many significant digits.
// to_chars ignores the locale, so "." is always the decimal point.
void put(std::ostream& out, double v, int digits = 0) {
  char buf[64];
  const auto r = digits > 0 ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits)
                            : std::to_chars(buf, buf + sizeof buf, v);
  out.write(buf, r.ptr - buf);
}

std::string xml_escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      default: r += c;
    }
  }
  return r;
}

[[noreturn]] void reject(const std::string& path, const std::string& why) {
  throw std::runtime_error("cannot write '" + path + "': " + why);
}

void check_points(const std::string& path, const std::vector<Vec3>& points) {
  for (size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) reject(path, "point " + std::to_string(i) + " is not finite");
}

// VTK_HEXAHEDRON lists the bottom face (z = 0) counter-clockwise seen from +z, then the top
// face above it. Paper node of a corner with bits (x, y, z) is 4x + 2y + z.
constexpr std::array<std::array<int, 3>, 8> kVtkCornerBits = {{
    {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};

constexpr std::array<int, 8> vtk_to_paper() {
  std::array<int, 8> p{};
  for (int k = 0; k < 8; ++k) p[k] = 4 * kVtkCornerBits[k][0] + 2 * kVtkCornerBits[k][1] + kVtkCornerBits[k][2];
  return p;
}
constexpr std::array<int, 8> kVtkToPaper = vtk_to_paper();

}  // namespace

void write_obj(const std::string& path, const TriMesh& mesh) {
  check_points(path, mesh.vertices);
  const int n = static_cast<int>(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t])
      if (v < 0 || v >= n) reject(path, "triangle " + std::to_string(t) + " has vertex index out of range");

  write_file_atomically(path, [&](std::ostream& out) {
    for (const Vec3& p : mesh.vertices) {
      out << 'v';
      for (int k = 0; k < 3; ++k) {
        out << ' ';
        put(out, p[k], 9);
      }
      out << '\n';
    }
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  });
}

void write_vtu(const std::string& path, const std::vector<Vec3>& points,
               const std::vector<std::array<int, 8>>& cells,
               const std::map<std::string, std::vector<double>>& cell_fields) {
  check_points(path, points);
  const int n = static_cast<int>(points.size());
  // A cell with -1 in slots 4-7 is a tetrahedron (VTK type 10), else a hexahedron (12).
  const auto is_tet = [](const std::array<int, 8>& cell) { return cell[4] < 0; };
  for (size_t c = 0; c < cells.size(); ++c)
    for (int k = 0; k < (is_tet(cells[c]) ? 4 : 8); ++k)
      if (cells[c][k] < 0 || cells[c][k] >= n) reject(path, "cell " + std::to_string(c) + " has node index out of range");
  for (const auto& [name, values] : cell_fields) {
    if (name.empty()) reject(path, "cell field with empty name");
    if (values.size() != cells.size())
      reject(path, "cell field '" + name + "' has " + std::to_string(values.size()) + " values for " +
                       std::to_string(cells.size()) + " cells");
    for (size_t c = 0; c < values.size(); ++c)
      if (!std::isfinite(values[c]))
        reject(path, "cell field '" + name + "' is not finite at cell " + std::to_string(c));
  }

  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\"" << cells.size() << "\">\n"
        << "      <Points>\n"
           "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& p : points) {
      out << "         ";
      for (int k = 0; k < 3; ++k) {
        out << ' ';
        put(out, p[k]);
      }
      out << '\n';
    }
    out << "        </DataArray>\n"
           "      </Points>\n"
           "      <Cells>\n"
           "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const auto& cell : cells) {
      out << "         ";
      if (is_tet(cell))
        for (int k = 0; k < 4; ++k) out << ' ' << cell[k];
      else
        for (int k = 0; k < 8; ++k) out << ' ' << cell[kVtkToPaper[k]];
      out << '\n';
    }
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    long offset = 0;
    for (const auto& cell : cells) out << "          " << (offset += is_tet(cell) ? 4 : 8) << '\n';
    out << "        </DataArray>\n"
           "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (const auto& cell : cells) out << (is_tet(cell) ? "          10\n" : "          12\n");
    out << "        </DataArray>\n"
           "      </Cells>\n"
           "      <CellData>\n";
    for (const auto& [name, values] : cell_fields) {
      out << "        <DataArray type=\"Float64\" Name=\"" << xml_escape(name) << "\" format=\"ascii\">\n";
      for (double v : values) {
        out << "          ";
        put(out, v);
        out << '\n';
      }
      out << "        </DataArray>\n";
    }
    out << "      </CellData>\n"
           "    </Piece>\n"
           "  </UnstructuredGrid>\n"
           "</VTKFile>\n";
  });
}

PvdCollection::PvdCollection(std::string directory, std::string name)
    : m_directory(std::move(directory)), m_name(std::move(name)) {}

void PvdCollection::add(double time, const std::string& vtu_file_name) {
  const std::string path = (std::filesystem::path(m_directory) / (m_name + ".pvd")).string();
  if (!std::isfinite(time)) reject(path, "time of '" + vtu_file_name + "' is not finite");
  m_entries.emplace_back(time, vtu_file_name);
  try {
    write_file_atomically(path, [&](std::ostream& out) {
      out << "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
             "  <Collection>\n";
      for (const auto& [t, file] : m_entries) {
        out << "    <DataSet timestep=\"";
        put(out, t);
        out << "\" group=\"\" part=\"0\" file=\"" << xml_escape(file) << "\"/>\n";
      }
      out << "  </Collection>\n"
             "</VTKFile>\n";
    });
  } catch (...) {
    m_entries.pop_back();  // the file on disk does not list it either
    throw;
  }
}

}  // namespace sinew
