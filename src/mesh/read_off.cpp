// OFF reader (Geomview's Object File Format, ASCII): "OFF" (or COFF/NOFF/CNOFF/STOFF...),
// counts, vertex lines, then one polygon per line ("n i1 ... in [colour]"). '#' starts a comment.
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "io/text_scan.hpp"

namespace frep {
namespace {
using namespace detail;

// Next non-empty line with comments removed; false at end of input.
bool next_content_line(LineCursor& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (auto h = line.find('#'); h != std::string_view::npos) line = line.substr(0, h);
    TokenSplitter t(line);
    std::string_view tok;
    if (t.next(tok)) return true;
  }
  return false;
}

}  // namespace

TriMesh read_off(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw InputError(name, 0, "empty file");
  LineCursor lines(bytes);
  std::string_view line;
  if (!next_content_line(lines, line)) throw InputError(name, 1, "empty OFF file");
  TokenSplitter head(line);
  std::string_view kw;
  head.next(kw);
  // The keyword may carry prefixes: ST (texture), C (colour), N (normal), 4 (4D), n (N-D).
  std::string_view core = kw;
  if (core.size() < 3 || core.substr(core.size() - 3) != "OFF")
    throw InputError(name, lines.line_no(), "not an OFF file (expected 'OFF' header, found '" + printable(kw) + "')");
  const std::string_view prefix = core.substr(0, core.size() - 3);
  if (prefix.find('4') != std::string_view::npos || prefix.find('n') != std::string_view::npos)
    throw InputError(name, lines.line_no(), "OFF variant '" + printable(kw) + "' (not 3D) is not supported");
  std::string_view tok;
  if (head.next(tok) && tok == "BINARY")
    throw InputError(name, lines.line_no(), "binary OFF is not supported");
  // Counts may follow the keyword on the same line or sit on the next content line.
  std::vector<std::int64_t> counts;
  auto take_counts = [&](TokenSplitter& t, std::string_view first) {
    std::string_view c = first;
    do {
      std::int64_t v;
      if (!parse_int(c, v) || v < 0)
        throw InputError(name, lines.line_no(), "bad OFF count '" + printable(c) + "'");
      counts.push_back(v);
    } while (counts.size() < 3 && t.next(c));
  };
  if (!tok.empty() && tok != "BINARY") take_counts(head, tok);
  if (counts.empty()) {
    if (!next_content_line(lines, line)) throw InputError(name, lines.line_no(), "OFF file ends before its counts");
    TokenSplitter t(line);
    t.next(tok);
    take_counts(t, tok);
  }
  if (counts.size() < 2) throw InputError(name, lines.line_no(), "OFF counts need vertex and face numbers");
  const std::uint64_t nv = counts[0], nf = counts[1];
  const std::uint64_t left = bytes.size() - std::min(lines.pos(), bytes.size());
  // Every vertex line needs at least "x y z\n" (6 bytes), every face line "3 a b c\n" (8).
  if (nv > left / 6 || nf > left / 8 || nv >= 0xffffffffu)
    throw InputError(name, lines.line_no(),
                     "OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                         " faces but only " + std::to_string(left) + " bytes follow");
  TriMesh m;
  m.name = name;
  m.vertices.reserve(nv);
  for (std::uint64_t v = 0; v < nv; ++v) {
    if (!next_content_line(lines, line))
      throw InputError(name, lines.line_no(), "OFF file ends after " + std::to_string(v) + " of " +
                                                  std::to_string(nv) + " vertices");
    TokenSplitter t(line);
    Vec3 p;
    for (int c = 0; c < 3; ++c) {
      if (!t.next(tok)) throw InputError(name, lines.line_no(), "vertex needs 3 coordinates");
      if (!parse_double(tok, p[c]))
        throw InputError(name, lines.line_no(), "bad vertex coordinate '" + printable(tok) + "'");
      if (!std::isfinite(p[c])) throw InputError(name, lines.line_no(), "vertex coordinate is not a finite number");
    }
    m.vertices.push_back(p);
  }
  std::vector<std::uint32_t> poly;
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!next_content_line(lines, line))
      throw InputError(name, lines.line_no(), "OFF file ends after " + std::to_string(f) + " of " +
                                                  std::to_string(nf) + " faces");
    const auto ln = static_cast<std::uint32_t>(lines.line_no());
    TokenSplitter t(line);
    std::int64_t n;
    t.next(tok);
    if (!parse_int(tok, n) || n < 0) throw InputError(name, ln, "bad polygon size '" + printable(tok) + "'");
    poly.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      std::int64_t i;
      if (!t.next(tok)) throw InputError(name, ln, "face lists fewer than " + std::to_string(n) + " vertices");
      if (!parse_int(tok, i) || i < 0 || std::uint64_t(i) >= nv)
        throw InputError(name, ln, "bad face index '" + printable(tok) + "' (" + std::to_string(nv) + " vertices)");
      poly.push_back(static_cast<std::uint32_t>(i));
    }
    if (n < 3) throw InputError(name, ln, "face with " + std::to_string(n) + " vertices");
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      m.add_triangle(poly[0], poly[k], poly[k + 1], static_cast<std::uint32_t>(f), ln);
    // Anything after the indices is a colour and is ignored.
  }
  if (m.triangles.empty()) throw InputError(name, 0, "OFF file has no faces");
  return m;
}

}  // namespace frep
