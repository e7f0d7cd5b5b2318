// Gmsh .msh (ASCII 2.2 and 4.1) reader. The file is read into one buffer and split into
// lines and tokens by hand with std::from_chars, as the OBJ reader does. Gmsh writes one
// record per line (a node, a node tag, a coordinate triple, an element), which lets a
// truncated or garbled record be reported on its own line.
#include "engine/geometry/gmsh_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "engine/core/error.hpp"
#include "engine/geometry/text_file.hpp"

namespace sinew {

namespace {

// The non-blank lines of a file, split into tokens.
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
      while (q < eol) {
        while (q < eol && is_blank(*q)) ++q;
        const char* b = q;
        while (q < eol && !is_blank(*q)) ++q;
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

  // `count` capped by the lines left (2 bytes each at least): what to reserve for `count`
  // records, so that a forged count does not reserve gigabytes.
  std::size_t at_most_lines(long count) const {
    return std::min(std::size_t(count), std::size_t(end - p) / 2);
  }

  // The next line, which must exist: `what` names the record expected there.
  void require_next(const std::string& what) {
    if (!next()) throw error("expected " + what + ", found the end of the file");
  }

  void require_tokens(std::size_t n, const std::string& what) const {
    if (tokens.size() != n)
      throw error("expected " + what + " (" + std::to_string(n) + " fields), got " +
                  std::to_string(tokens.size()) + " fields");
  }

  long integer(std::size_t i, const char* what) const {
    std::string_view tok = tokens[i];
    if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
    long v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size())
      throw error(std::string("expected ") + what + " (an integer), got '" +
                  std::string(tokens[i]) + "'");
    return v;
  }

  long count(std::size_t i, const char* what) const {
    const long v = integer(i, what);
    if (v < 0 || v > 0x7fffffffL)
      throw error(std::string("expected ") + what + " (an integer >= 0), got " + std::to_string(v));
    return v;
  }

  double real(std::size_t i) const {
    std::string_view tok = tokens[i];
    if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);  // from_chars rejects '+'
    double v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size() || !std::isfinite(v))
      throw error("expected a finite coordinate, got '" + std::string(tokens[i]) + "'");
    return v;
  }

  void require_end(const char* end_tag) {
    require_next(end_tag);
    if (tokens.size() != 1 || tokens[0] != end_tag)
      throw error(std::string("expected ") + end_tag +
                  " after the count the section header announces, got '" + std::string(tokens[0]) +
                  "'");
  }
};

constexpr int kTet4 = 4;  // Gmsh element type of the 4-node tetrahedron

struct Reader {
  explicit Reader(Lines lines) : in(std::move(lines)) {}

  Lines in;
  int version = 0;  // 2 (2.x) or 4 (4.1); 0 until $MeshFormat is read
  bool have_nodes = false, have_elements = false;
  long elements_line = 0;
  std::unordered_map<long, int> node_of_tag;
  TetMesh mesh;
  std::vector<long> tet_lines;         // line of each kept tet
  std::map<long, long> skipped_types;  // element type -> count, of the elements not kept

  void read_format() {
    in.require_next("'<version> <file-type> <data-size>'");
    if (in.tokens.size() < 3) in.require_tokens(3, "'<version> <file-type> <data-size>'");
    if (in.tokens[1] != "0")
      throw in.error("expected an ASCII file (file-type 0), got file-type " +
                     std::string(in.tokens[1]) +
                     ": binary .msh files are not supported; save the mesh again as ASCII (Gmsh "
                     "option Mesh.Binary = 0)");
    const std::string v(in.tokens[0]);
    if (v == "2" || v == "2.0" || v == "2.1" || v == "2.2")
      version = 2;  // one syntax for 2.x
    else if (v == "4.1")
      version = 4;
    else
      throw in.error("expected MSH format version 2.2 or 4.1, got " + v);
    in.require_end("$EndMeshFormat");
  }

  void add_node(long tag) {
    if (!node_of_tag.emplace(tag, int(mesh.nodes.size())).second)
      throw in.error("expected each node tag once, tag " + std::to_string(tag) + " repeats");
  }

  // 2.2: "<count>", then "<tag> <x> <y> <z>" per node.
  void read_nodes_v2() {
    in.require_next("the number of nodes");
    in.require_tokens(1, "'<number of nodes>'");
    const long n = in.count(0, "the number of nodes");
    mesh.nodes.reserve(in.at_most_lines(n));
    for (long i = 0; i < n; ++i) {
      in.require_next("node " + std::to_string(i + 1) + " of " + std::to_string(n));
      in.require_tokens(4, "'<tag> <x> <y> <z>'");
      add_node(in.integer(0, "a node tag"));
      mesh.nodes.emplace_back(in.real(1), in.real(2), in.real(3));
    }
    in.require_end("$EndNodes");
  }

  // 4.1: "<blocks> <nodes> <min tag> <max tag>"; per block "<dim> <entity> <parametric>
  // <count>", then <count> lines of one tag, then <count> lines "x y z [u [v [w]]]".
  void read_nodes_v41() {
    in.require_next("'<blocks> <nodes> <min tag> <max tag>'");
    in.require_tokens(4, "'<blocks> <nodes> <min tag> <max tag>'");
    const long blocks = in.count(0, "the number of entity blocks");
    const long total = in.count(1, "the number of nodes");
    mesh.nodes.reserve(in.at_most_lines(total));
    for (long b = 0; b < blocks; ++b) {
      in.require_next("node block " + std::to_string(b + 1) + " of " + std::to_string(blocks));
      in.require_tokens(4, "a node block header '<dim> <entity tag> <parametric> <count>'");
      const long dim = in.integer(0, "the entity dimension");
      const long parametric = in.integer(2, "the parametric flag");
      const long n = in.count(3, "the number of nodes in the block");
      if (dim < 0 || dim > 3)
        throw in.error("expected an entity dimension 0..3, got " + std::to_string(dim));
      if (parametric != 0 && parametric != 1)
        throw in.error("expected the parametric flag 0 or 1, got " + std::to_string(parametric));
      if (long(mesh.nodes.size()) + n > total)
        throw in.error("expected at most " + std::to_string(total) +
                       " nodes in all (the section header), the blocks hold more");
      const std::size_t first = mesh.nodes.size();
      for (long i = 0; i < n; ++i) {
        in.require_next("a node tag");
        in.require_tokens(1, "a node tag");
        if (!node_of_tag.emplace(in.integer(0, "a node tag"), int(first + i)).second)
          throw in.error("expected each node tag once, tag " + std::string(in.tokens[0]) +
                         " repeats");
      }
      const std::size_t fields = 3 + (parametric ? std::size_t(dim) : 0);
      for (long i = 0; i < n; ++i) {
        in.require_next("node coordinates");
        in.require_tokens(
            fields, parametric ? "'<x> <y> <z>' and the parametric coordinates" : "'<x> <y> <z>'");
        mesh.nodes.emplace_back(in.real(0), in.real(1), in.real(2));
      }
    }
    if (long(mesh.nodes.size()) != total)
      throw in.error("expected " + std::to_string(total) +
                     " nodes as the section header says, the blocks hold " +
                     std::to_string(mesh.nodes.size()));
    in.require_end("$EndNodes");
  }

  // Node tags of a tet from tokens [first, first + 4).
  void add_tet(std::size_t first) {
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      const long tag = in.integer(first + k, "a node tag");
      const auto it = node_of_tag.find(tag);
      if (it == node_of_tag.end())
        throw in.error("expected the tag of a node of $Nodes, got " + std::to_string(tag) +
                       " (no such node)");
      tet[k] = it->second;
      for (int m = 0; m < k; ++m)
        if (tet[m] == tet[k])
          throw in.error("expected 4 distinct nodes, node tag " + std::to_string(tag) + " repeats");
    }
    mesh.tets.push_back(tet);
    tet_lines.push_back(in.line);
  }

  // 2.2: "<count>", then "<tag> <type> <#tags> <tags...> <nodes...>" per element.
  void read_elements_v2() {
    in.require_next("the number of elements");
    in.require_tokens(1, "'<number of elements>'");
    const long n = in.count(0, "the number of elements");
    for (long i = 0; i < n; ++i) {
      in.require_next("element " + std::to_string(i + 1) + " of " + std::to_string(n));
      if (in.tokens.size() < 3) in.require_tokens(3, "at least '<tag> <type> <number of tags>'");
      const long type = in.integer(1, "an element type");
      const long n_tags = in.count(2, "the number of tags");
      if (type != kTet4) {
        ++skipped_types[type];
        continue;
      }
      in.require_tokens(std::size_t(3 + n_tags + 4),
                        "'<tag> 4 <#tags> <tags> <4 node tags>' (a 4-node tetrahedron)");
      add_tet(std::size_t(3 + n_tags));
    }
    in.require_end("$EndElements");
  }

  // 4.1: "<blocks> <elements> <min tag> <max tag>"; per block "<dim> <entity> <type>
  // <count>", then <count> lines "<tag> <node tags...>".
  void read_elements_v41() {
    in.require_next("'<blocks> <elements> <min tag> <max tag>'");
    in.require_tokens(4, "'<blocks> <elements> <min tag> <max tag>'");
    const long blocks = in.count(0, "the number of entity blocks");
    const long total = in.count(1, "the number of elements");
    long seen = 0;
    for (long b = 0; b < blocks; ++b) {
      in.require_next("element block " + std::to_string(b + 1) + " of " + std::to_string(blocks));
      in.require_tokens(4, "an element block header '<dim> <entity tag> <element type> <count>'");
      const long type = in.integer(2, "an element type");
      const long n = in.count(3, "the number of elements in the block");
      for (long i = 0; i < n; ++i) {
        in.require_next("element " + std::to_string(i + 1) + " of " + std::to_string(n) +
                        " in block " + std::to_string(b + 1));
        if (type != kTet4) {
          ++skipped_types[type];
          continue;
        }
        in.require_tokens(5, "'<tag> <4 node tags>' (a 4-node tetrahedron)");
        add_tet(1);
      }
      seen += n;
    }
    if (seen != total)
      throw in.error("expected " + std::to_string(total) +
                     " elements as the section header says, the blocks hold " +
                     std::to_string(seen));
    in.require_end("$EndElements");
  }

  void skip_section(const std::string& name) {
    const long start = in.line;
    const std::string end_tag = "$End" + name.substr(1);
    while (in.next())
      if (in.tokens[0] == end_tag) return;
    throw in.error("expected " + end_tag + " to close the section opened on line " +
                   std::to_string(start) + ", found the end of the file");
  }

  // "12 triangles, 3 lines": what the file holds instead of tets.
  std::string skipped_summary() const {
    static const std::map<long, const char*> names{{1, "lines"},
                                                   {2, "triangles"},
                                                   {3, "quadrangles"},
                                                   {5, "hexahedra"},
                                                   {6, "prisms"},
                                                   {7, "pyramids"},
                                                   {8, "quadratic lines"},
                                                   {9, "quadratic triangles"},
                                                   {11, "10-node tetrahedra"},
                                                   {15, "points"}};
    std::string s;
    for (const auto& [type, n] : skipped_types) {
      if (!s.empty()) s += ", ";
      const auto it = names.find(type);
      s += std::to_string(n) + " " +
           (it != names.end() ? it->second : "elements of type " + std::to_string(type));
    }
    return s.empty() ? "no elements" : s;
  }

  // Gmsh's 3D element types (hexahedra, prisms, pyramids and their higher orders).
  bool has_volume_elements() const {
    for (const auto& [type, n] : skipped_types)
      if (type == 5 || type == 6 || type == 7 || type == 11 || type == 12 || type == 13 ||
          type == 14 || type == 17 || type == 18 || type == 19 || type == 29 || type == 30 ||
          type == 31)
        return true;
    return false;
  }
};

}  // namespace

TetMeshFile read_gmsh(const std::string& path) {
  const std::string data = read_whole_file(path);
  Reader r(Lines(path, data));
  Lines& in = r.in;
  while (in.next()) {
    const std::string name(in.tokens[0]);
    if (name.size() < 2 || name[0] != '$')
      throw in.error("expected a section header such as $Nodes, got '" + name + "'");
    if (r.version == 0 && name != "$MeshFormat")
      throw in.error("expected $MeshFormat as the first section of a .msh file, got " + name);
    if (name == "$MeshFormat") {
      if (r.version != 0) throw in.error("expected one $MeshFormat section, found a second");
      r.read_format();
    } else if (name == "$Nodes") {
      if (r.have_nodes) throw in.error("expected one $Nodes section, found a second");
      r.version == 2 ? r.read_nodes_v2() : r.read_nodes_v41();
      r.have_nodes = true;
    } else if (name == "$Elements") {
      if (!r.have_nodes) throw in.error("expected $Nodes before $Elements");
      if (r.have_elements) throw in.error("expected one $Elements section, found a second");
      r.elements_line = in.line;
      r.version == 2 ? r.read_elements_v2() : r.read_elements_v41();
      r.have_elements = true;
    } else {
      r.skip_section(name);
    }
  }
  if (r.version == 0)
    throw in.error("expected a Gmsh mesh starting with $MeshFormat, found an empty file");
  if (!r.have_nodes) throw in.error("expected a $Nodes section, found the end of the file");
  if (!r.have_elements) throw in.error("expected an $Elements section, found the end of the file");
  if (r.mesh.tets.empty()) {
    in.line = r.elements_line;
    if (r.has_volume_elements())
      throw in.error("expected 4-node tetrahedra (element type 4), found none: the file holds " +
                     r.skipped_summary() +
                     "; sinew reads linear tetrahedra only (Gmsh option Mesh.ElementOrder = 1)");
    throw in.error(
        "expected 4-node tetrahedra (element type 4), found none: this is a surface-only mesh (" +
        r.skipped_summary() + "); mesh the volume in Gmsh (3D mesh, gmsh -3)");
  }

  TetMeshFile out;
  out.mesh = std::move(r.mesh);
  std::vector<int> degenerate;
  out.reoriented = orient_tets_positively(out.mesh, &degenerate);
  if (!degenerate.empty()) {
    in.line = r.tet_lines[degenerate.front()];
    throw in.error("expected a tetrahedron of nonzero volume, its nodes are (nearly) coplanar (" +
                   std::to_string(degenerate.size()) + " such tetrahedra in the file)");
  }
  out.unreferenced_nodes = count_unreferenced_nodes(out.mesh);
  return out;
}

}  // namespace sinew
