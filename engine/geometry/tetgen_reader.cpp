// TetGen .node/.ele reader. Each file is read into one buffer and split into lines and
// tokens by hand with std::from_chars, as the OBJ reader does.
#include "engine/geometry/tetgen_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string_view>
#include <utility>

#include "engine/core/error.hpp"
#include "engine/geometry/text_file.hpp"

namespace sinew {

namespace {

// The data lines of a file: blank lines and '#' comments skipped.
struct Lines {
  std::string path;
  const char* p;
  const char* end;
  long line = 0;  // number of the line `tokens` came from
  std::vector<std::string_view> tokens;

  Lines(std::string file, const std::string& data)
      : path(std::move(file)), p(data.data()), end(data.data() + data.size()) {}

  // Advances to the next line holding a token; false (and no tokens) at the end of the file.
  bool next() {
    tokens.clear();
    while (p < end) {
      ++line;
      const char* eol = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
      if (!eol) eol = end;
      const char* q = p;
      while (q < eol && *q != '#') {
        while (q < eol && is_blank(*q)) ++q;
        const char* b = q;
        while (q < eol && !is_blank(*q) && *q != '#') ++q;
        if (q > b) tokens.emplace_back(b, std::size_t(q - b));
      }
      p = eol < end ? eol + 1 : end;
      if (!tokens.empty()) return true;
    }
    return false;
  }

  InputError error(const std::string& what) const {
    return InputError(path + ":" + std::to_string(line) + ": " + what);
  }
};

bool parse_long(std::string_view tok, long& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return !tok.empty() && ec == std::errc() && ptr == tok.data() + tok.size();
}

bool parse_double(std::string_view tok, double& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);  // from_chars rejects '+'
  if (tok.empty()) return false;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && ptr == tok.data() + tok.size() && std::isfinite(out);
}

// Header fields: token i as an integer in [lo, hi], or `fallback` when the line is shorter.
long header_field(const Lines& in, std::size_t i, long fallback, long lo, long hi,
                  const char* what) {
  if (i >= in.tokens.size()) return fallback;
  long v = 0;
  if (!parse_long(in.tokens[i], v) || v < lo || v > hi)
    throw in.error(std::string("expected ") + what + ", got '" + std::string(in.tokens[i]) + "'");
  return v;
}

struct NodeFile {
  std::vector<Vec3> nodes;
  long base = 0;  // index of the first node: 0 or 1
};

NodeFile read_node_file(const std::string& path) {
  const std::string data = read_whole_file(path);
  Lines in(path, data);
  if (!in.next())
    throw in.error(
        "expected the header '<#points> 3 <#attributes> <#markers>', found an empty file");
  if (in.tokens.size() > 4)
    throw in.error("expected a header of at most 4 numbers, got " +
                   std::to_string(in.tokens.size()));
  const long count =
      header_field(in, 0, 0, 1, 0x7fffffffL, "the number of points (a positive integer)");
  header_field(in, 1, 3, 3, 3, "dimension 3");
  const long n_attributes =
      header_field(in, 2, 0, 0, 1000, "the number of attributes (an integer >= 0)");
  const long n_markers = header_field(in, 3, 0, 0, 1, "the boundary marker flag 0 or 1");
  const std::size_t n_tokens = std::size_t(4 + n_attributes + n_markers);

  NodeFile out;
  // Reserve no more than the file can hold (a point's line is 8 bytes, "0 0 0 0\n", or more):
  // a forged count must not reserve gigabytes.
  out.nodes.reserve(std::min(std::size_t(count), data.size() / 8));
  for (long i = 0; i < count; ++i) {
    if (!in.next())
      throw in.error("expected " + std::to_string(count) +
                     " points as the header says, the file ends after " + std::to_string(i));
    if (in.tokens.size() != n_tokens)
      throw in.error("expected " + std::to_string(n_tokens) + " fields '<index> <x> <y> <z>" +
                     (n_attributes ? " <attributes>" : "") + (n_markers ? " <marker>" : "") +
                     "', got " + std::to_string(in.tokens.size()));
    long index = 0;
    if (!parse_long(in.tokens[0], index))
      throw in.error("expected a point index (integer), got '" + std::string(in.tokens[0]) + "'");
    if (i == 0) {
      if (index != 0 && index != 1)
        throw in.error("expected the first point index to be 0 or 1, got " + std::to_string(index));
      out.base = index;
    } else if (index != out.base + i) {
      throw in.error("expected point index " + std::to_string(out.base + i) +
                     " (consecutive), got " + std::to_string(index));
    }
    double c[3];
    for (int k = 0; k < 3; ++k)
      if (!parse_double(in.tokens[1 + k], c[k]))
        throw in.error("expected a finite coordinate, got '" + std::string(in.tokens[1 + k]) + "'");
    out.nodes.emplace_back(c[0], c[1], c[2]);
  }
  if (in.next())
    throw in.error("expected the end of the file after the " + std::to_string(count) +
                   " points the header announces");
  return out;
}

// Tets in 0-based node indices, with the line of each (for later errors).
void read_ele_file(const std::string& path, const NodeFile& nodes, TetMesh& mesh,
                   std::vector<long>& lines) {
  const std::string data = read_whole_file(path);
  Lines in(path, data);
  if (!in.next())
    throw in.error("expected the header '<#tetrahedra> <4|10> <#attributes>', found an empty file");
  if (in.tokens.size() > 3)
    throw in.error("expected a header of at most 3 numbers, got " +
                   std::to_string(in.tokens.size()));
  const long count =
      header_field(in, 0, 0, 1, 0x7fffffffL, "the number of tetrahedra (a positive integer)");
  const long per_tet = header_field(in, 1, 4, 4, 10, "4 or 10 nodes per tetrahedron");
  if (per_tet != 4 && per_tet != 10)
    throw in.error("expected 4 or 10 nodes per tetrahedron, got " + std::to_string(per_tet));
  const long n_attributes =
      header_field(in, 2, 0, 0, 1000, "the number of attributes (an integer >= 0)");
  const std::size_t n_tokens = std::size_t(1 + per_tet + n_attributes);
  const long n_nodes = long(nodes.nodes.size());

  // Reserve no more than the file can hold (a tet's line is 10 bytes, "0 0 1 2 3\n", or more).
  const std::size_t capacity = std::min(std::size_t(count), data.size() / 10);
  mesh.tets.reserve(capacity);
  lines.reserve(capacity);
  for (long i = 0; i < count; ++i) {
    if (!in.next())
      throw in.error("expected " + std::to_string(count) +
                     " tetrahedra as the header says, the file ends after " + std::to_string(i));
    if (in.tokens.size() != n_tokens)
      throw in.error("expected " + std::to_string(n_tokens) + " fields '<index> <" +
                     std::to_string(per_tet) + " nodes>" + (n_attributes ? " <attributes>" : "") +
                     "', got " + std::to_string(in.tokens.size()));
    long index = 0;
    if (!parse_long(in.tokens[0], index))
      throw in.error("expected a tetrahedron index (integer), got '" + std::string(in.tokens[0]) +
                     "'");
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      long n = 0;
      if (!parse_long(in.tokens[1 + k], n))
        throw in.error("expected a node index (integer), got '" + std::string(in.tokens[1 + k]) +
                       "'");
      if (n < nodes.base || n >= nodes.base + n_nodes)
        throw in.error("expected a node index in [" + std::to_string(nodes.base) + ", " +
                       std::to_string(nodes.base + n_nodes - 1) +
                       "] (the points of the .node file), got " + std::to_string(n));
      tet[k] = int(n - nodes.base);
      for (int m = 0; m < k; ++m)
        if (tet[m] == tet[k])
          throw in.error("expected 4 distinct nodes, node " + std::to_string(n) + " repeats");
    }
    mesh.tets.push_back(tet);
    lines.push_back(in.line);
  }
  if (in.next())
    throw in.error("expected the end of the file after the " + std::to_string(count) +
                   " tetrahedra the header announces");
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

TetMeshFile read_tetgen(const std::string& path) {
  std::string base = path;
  if (ends_with(base, ".node"))
    base.resize(base.size() - 5);
  else if (ends_with(base, ".ele"))
    base.resize(base.size() - 4);
  const std::string node_path = base + ".node", ele_path = base + ".ele";
  if (!std::filesystem::exists(node_path))
    throw InputError(node_path +
                     ": cannot open file for reading (expected the points of TetGen mesh '" + path +
                     "')");
  const NodeFile nodes = read_node_file(node_path);
  if (!std::filesystem::exists(ele_path))
    throw InputError(
        node_path + ": expected its tetrahedra in " + ele_path +
        ", which does not exist (a .node file alone is a point set, not a volume mesh)");

  TetMeshFile out;
  std::vector<long> lines;
  read_ele_file(ele_path, nodes, out.mesh, lines);
  out.mesh.nodes = nodes.nodes;

  std::vector<int> degenerate;
  out.reoriented = orient_tets_positively(out.mesh, &degenerate);
  if (!degenerate.empty()) {
    const auto& t = out.mesh.tets[degenerate.front()];
    std::string ids;
    for (int n : t) ids.append(" ").append(std::to_string(n + nodes.base));
    throw InputError(ele_path + ":" + std::to_string(lines[degenerate.front()]) +
                     ": expected a tetrahedron of nonzero volume, nodes" + ids +
                     " are (nearly) coplanar (" + std::to_string(degenerate.size()) +
                     " such tetrahedra in the file)");
  }
  out.unreferenced_nodes = count_unreferenced_nodes(out.mesh);
  return out;
}

}  // namespace sinew
