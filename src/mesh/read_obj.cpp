// Wavefront OBJ reader: positions and faces only. Polygons are fan-triangulated; indices may be
// negative (relative to the vertices read so far) and carry /vt/vn parts, which are ignored.
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "frep/util/text_scan.hpp"

namespace frep {
namespace {
using namespace detail;

bool is_keyword_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

}  // namespace

TriMesh read_obj(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw InputError(name, 0, "empty file");
  TriMesh m;
  m.name = name;
  LineCursor lines(bytes);
  std::string_view raw;
  std::string joined;  // a logical line assembled from backslash-continued physical lines
  std::vector<std::int64_t> poly;
  std::uint32_t face = 0;
  while (lines.next(raw)) {
    const std::uint64_t line_no = lines.line_no();
    std::string_view line = raw;
    // Backslash at the end of a line continues it on the next one.
    auto trimmed_end = [](std::string_view s) {
      while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
      return s;
    };
    if (std::string_view t = trimmed_end(line); !t.empty() && t.back() == '\\') {
      joined.assign(t.substr(0, t.size() - 1));
      std::string_view more;
      while (lines.next(more)) {
        std::string_view mt = trimmed_end(more);
        if (!mt.empty() && mt.back() == '\\') {
          joined += ' ';
          joined.append(mt.substr(0, mt.size() - 1));
          continue;
        }
        joined += ' ';
        joined.append(mt);
        break;
      }
      line = joined;
    }
    if (auto h = line.find('#'); h != std::string_view::npos) line = line.substr(0, h);
    TokenSplitter tokens(line);
    std::string_view kw;
    if (!tokens.next(kw)) continue;
    for (char c : kw)
      if (!is_keyword_char(c))
        throw InputError(name, line_no, "not an OBJ statement: '" + printable(kw) + "'");
    if (kw == "v") {
      Vec3 p;
      for (int c = 0; c < 3; ++c) {
        std::string_view tok;
        if (!tokens.next(tok)) throw InputError(name, line_no, "vertex needs 3 coordinates");
        if (!parse_double(tok, p[c]))
          throw InputError(name, line_no, "bad vertex coordinate '" + printable(tok) + "'");
        if (!std::isfinite(p[c])) throw InputError(name, line_no, "vertex coordinate is not a finite number");
      }
      // What may follow: w, or a colour (r g b), as numbers.
      for (std::string_view tok; tokens.next(tok);) {
        double extra;
        if (!parse_double(tok, extra))
          throw InputError(name, line_no, "unexpected '" + printable(tok) + "' after the vertex coordinates");
      }
      if (m.vertices.size() >= 0xffffffffu) throw InputError(name, line_no, "too many vertices");
      m.vertices.push_back(p);
    } else if (kw == "f" || kw == "fo") {
      poly.clear();
      std::string_view tok;
      while (tokens.next(tok)) {
        std::string_view idx = tok.substr(0, tok.find('/'));
        std::int64_t i;
        if (!parse_int(idx, i) || i == 0)
          throw InputError(name, line_no, "bad face index '" + printable(tok) + "'");
        if (i < 0) {
          i += static_cast<std::int64_t>(m.vertices.size());
          if (i < 0)
            throw InputError(name, line_no, "relative face index '" + printable(tok) + "' points before the first vertex");
        } else {
          i -= 1;
        }
        if (i >= 0xffffffffLL) throw InputError(name, line_no, "face index '" + printable(tok) + "' is too large");
        poly.push_back(i);
      }
      if (poly.size() < 3)
        throw InputError(name, line_no, "face with " + std::to_string(poly.size()) + " vertices");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        m.add_triangle(static_cast<std::uint32_t>(poly[0]), static_cast<std::uint32_t>(poly[k]),
                       static_cast<std::uint32_t>(poly[k + 1]), face, static_cast<std::uint32_t>(line_no));
      }
      ++face;
    }
    // Positive indices may point at vertices defined later; ranges are checked at the end.
    // Everything else (vt, vn, g, o, s, usemtl, mtllib, l, p, curves...) does not affect the
    // triangle surface and is skipped.
  }
  if (m.triangles.empty()) throw InputError(name, 0, "OBJ file has no faces");
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (std::uint32_t v : m.triangles[t])
      if (v >= m.vertices.size())
        throw InputError(name, m.origins[t].line,
                         "face index " + std::to_string(std::uint64_t(v) + 1) + " is beyond the " +
                             std::to_string(m.vertices.size()) + " vertices in the file");
  return m;
}

}  // namespace frep
