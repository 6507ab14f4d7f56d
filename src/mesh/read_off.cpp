// OFF reader (Geomview's Object File Format, ASCII): "OFF" (or COFF/NOFF/CNOFF/STOFF/4OFF/nOFF
// of dimension 3; optional), counts, vertices, then one polygon per line ("n i1 ... in [colour]").
// '#' starts a comment.
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "frep/util/text_scan.hpp"

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
  std::string_view kw, tok;
  head.next(kw);
  // The keyword may carry prefixes: ST (texture), C (colour), N (normal), 4 (homogeneous), n (N-D).
  // Geomview calls it optional (a file may start with its counts), and ModelNet's files glue the
  // counts to it ("OFF490 518 0").
  std::string_view prefix, after;  // `after`: what follows "OFF" in the same token
  bool keyword = false;
  if (const std::size_t at = kw.find("OFF"); at != std::string_view::npos) {
    prefix = kw.substr(0, at);
    after = kw.substr(at + 3);
    keyword = prefix.find_first_not_of("STCN4n") == std::string_view::npos &&
              (after.empty() || after.find_first_not_of("0123456789") == std::string_view::npos);
  }
  std::int64_t first_count;
  if (!keyword && !parse_int(kw, first_count))
    throw InputError(name, lines.line_no(), "not an OFF file (expected 'OFF' or the counts, found '" + printable(kw) + "')");
  const bool colours = prefix.find('C') != std::string_view::npos, normals = prefix.find('N') != std::string_view::npos,
             texture = prefix.find("ST") != std::string_view::npos;
  const bool homogeneous = prefix.find('4') != std::string_view::npos;
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
  auto next_token_line = [&](const char* what) {
    if (!next_content_line(lines, line)) throw InputError(name, lines.line_no(), std::string("OFF file ends before its ") + what);
    head = TokenSplitter(line);
    head.next(tok);
  };
  if (!keyword) {
    take_counts(head, kw);
  } else {
    const bool has_tok = !after.empty() ? (tok = after, true) : head.next(tok);
    if (has_tok && tok == "BINARY") throw InputError(name, lines.line_no(), "binary OFF is not supported");
    if (prefix.find('n') != std::string_view::npos) {
      // nOFF: the dimension comes first; only 3 is a solid in space.
      if (!has_tok) next_token_line("dimension");
      std::int64_t dim;
      if (!parse_int(tok, dim) || dim != 3)
        throw InputError(name, lines.line_no(), "OFF variant '" + printable(kw) + "' of dimension '" + printable(tok) +
                                                    "' is not supported (only 3)");
      if (!head.next(tok)) tok = {};
    } else if (!has_tok) {
      tok = {};
    }
    // Counts may follow the keyword on the same line or sit on the next content line.
    if (tok.empty()) next_token_line("counts");
    take_counts(head, tok);
  }
  if (counts.size() < 2) throw InputError(name, lines.line_no(), "OFF counts need vertex and face numbers");
  const std::uint64_t nv = counts[0], nf = counts[1];
  const std::uint64_t left = bytes.size() - std::min(lines.pos(), bytes.size());
  // Every vertex needs at least "x y z " (6 bytes), every face line "3 a b c\n" (8).
  if (nv > left / 6 || nf > left / 8 || nv >= 0xffffffffu)
    throw InputError(name, lines.line_no(),
                     "OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                         " faces but only " + std::to_string(left) + " bytes follow");
  TriMesh m;
  m.name = name;
  m.vertices.reserve(nv);
  // Vertices are values, not lines, in the format; files write one per line, with colours,
  // normals or texture coordinates after the position. Read by line unless the file has fewer
  // lines than vertices and faces (several vertices on a line), which only plain OFF allows.
  const int dims = homogeneous ? 4 : 3;
  bool by_line = colours || normals || texture;
  if (!by_line) {
    LineCursor probe = lines;
    std::uint64_t content = 0;
    std::string_view l;
    while (content < nv + nf && next_content_line(probe, l)) ++content;
    by_line = content >= nv + nf;
  }
  double value[4];
  TokenSplitter vt(std::string_view{});
  for (std::uint64_t v = 0; v < nv; ++v) {
    for (int c = 0; c < dims; ++c) {
      while (!vt.next(tok)) {
        if (by_line && c > 0) throw InputError(name, lines.line_no(), "vertex needs " + std::to_string(dims) + " coordinates");
        if (!next_content_line(lines, line))
          throw InputError(name, lines.line_no(), "OFF file ends after " + std::to_string(v) + " of " +
                                                      std::to_string(nv) + " vertices");
        vt = TokenSplitter(line);
      }
      if (!parse_double(tok, value[c]))
        throw InputError(name, lines.line_no(), "bad vertex coordinate '" + printable(tok) + "'");
      if (!std::isfinite(value[c])) throw InputError(name, lines.line_no(), "vertex coordinate is not a finite number");
    }
    if (homogeneous && value[3] == 0)
      throw InputError(name, lines.line_no(), "vertex with homogeneous coordinate w = 0 (a point at infinity)");
    const double w = homogeneous ? value[3] : 1;
    const Vec3 p{value[0] / w, value[1] / w, value[2] / w};
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(p[c])) throw InputError(name, lines.line_no(), "vertex coordinate is not a finite number");
    m.vertices.push_back(p);
    if (by_line) vt = TokenSplitter(std::string_view{});  // the rest of the line is colour, normal...
  }
  if (!by_line && vt.next(tok))
    throw InputError(name, lines.line_no(), "unexpected '" + printable(tok) + "' after the last vertex");
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
