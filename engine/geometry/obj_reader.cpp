// Wavefront OBJ reader. The whole file is read into one buffer and scanned by hand with
// std::from_chars: per-token iostream extraction is several times slower on big meshes.
#include "engine/geometry/obj_reader.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string_view>
#include <utility>

#include "engine/core/error.hpp"
#include "engine/geometry/text_file.hpp"

namespace sinew {

namespace {

// Cursor over one line; tokens end at blanks, end of line or a '#' comment.
struct LineScanner {
  const char* p;
  const char* end;

  void skip_blanks() {
    while (p < end && is_blank(*p)) ++p;
  }
  bool at_end() {
    skip_blanks();
    return p >= end || *p == '#';
  }
  std::string_view token() {
    skip_blanks();
    const char* b = p;
    while (p < end && !is_blank(*p) && *p != '#') ++p;
    return {b, std::size_t(p - b)};
  }
};

bool parse_double(std::string_view tok, double& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);  // from_chars rejects '+'
  if (tok.empty()) return false;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && ptr == tok.data() + tok.size() && std::isfinite(out);
}

// Leading vertex index of a face token ("7", "7/1", "7//2", "7/1/2").
bool parse_face_index(std::string_view tok, long& out) {
  const std::size_t slash = tok.find('/');
  std::string_view head = tok.substr(0, slash);
  if (!head.empty() && head.front() == '+') head.remove_prefix(1);
  if (head.empty()) return false;
  auto [ptr, ec] = std::from_chars(head.data(), head.data() + head.size(), out);
  return ec == std::errc() && ptr == head.data() + head.size();
}

}  // namespace

TriMesh read_obj(const std::string& path) {
  const std::string data = read_whole_file(path);
  TriMesh mesh;
  std::vector<int> face;          // 0-based indices of the current polygon
  // Positive indices past the vertices read so far (a later 'v' may define them), kept only
  // when they raise the running maximum: the first line that stays invalid is among them.
  std::vector<std::pair<long, long>> forward;  // (line, index)
  long line_no = 0;

  auto fail = [&](const std::string& what) -> InputError {
    return InputError(path + ":" + std::to_string(line_no) + ": " + what);
  };

  const char* p = data.data();
  const char* const end = data.data() + data.size();
  while (p < end) {
    ++line_no;
    const char* eol = p;
    while (eol < end && *eol != '\n') ++eol;
    LineScanner s{p, eol};
    p = eol + 1;

    const std::string_view kw = s.token();
    if (kw == "v") {
      double c[3];
      for (double& v : c) {
        const std::string_view tok = s.token();
        if (!parse_double(tok, v))
          throw fail("expected three finite numbers after 'v', got '" + std::string(tok) + "'");
      }
      mesh.vertices.emplace_back(c[0], c[1], c[2]);  // an optional w is ignored
    } else if (kw == "f") {
      face.clear();
      const long n_known = long(mesh.vertices.size());
      while (!s.at_end()) {
        const std::string_view tok = s.token();
        long idx = 0;
        if (!parse_face_index(tok, idx) || idx == 0)
          throw fail("expected a vertex index (nonzero integer) in 'f', got '" + std::string(tok) + "'");
        if (idx < 0) {
          // Relative to the vertices read so far: -1 is the latest one.
          if (idx < -n_known)  // not -idx > n_known: -LONG_MIN overflows
            throw fail("face index " + std::to_string(idx) + " is out of range (" +
                       std::to_string(n_known) + " vertices so far)");
          idx = n_known + idx + 1;
        } else if (idx > n_known && (forward.empty() || idx > forward.back().second)) {
          forward.emplace_back(line_no, idx);
        }
        if (idx > 0x7fffffffL) throw fail("face index " + std::to_string(idx) + " is out of range");
        face.push_back(int(idx - 1));
      }
      if (face.size() < 3)
        throw fail("expected at least 3 vertices in 'f', got " + std::to_string(face.size()));
      // Fan triangulation keeps the polygon's winding.
      for (std::size_t i = 1; i + 1 < face.size(); ++i)
        mesh.triangles.push_back({face[0], face[i], face[i + 1]});
    }
    // Every other record (vt, vn, o, g, s, usemtl, comments, ...) is ignored.
  }

  for (const auto& [line, idx] : forward) {
    if (idx <= long(mesh.vertices.size())) continue;
    line_no = line;
    throw fail("face index " + std::to_string(idx) + " is out of range (the file has " +
               std::to_string(mesh.vertices.size()) + " vertices)");
  }
  if (mesh.triangles.empty())
    throw fail("expected at least one face ('f' record) by the end of the file, found none");
  return mesh;
}

}  // namespace sinew
