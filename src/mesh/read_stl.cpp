// STL reader: ASCII and binary, told apart by content rather than by the "solid" prefix that
// many binary exporters put in their header.
#include <algorithm>
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "io/text_scan.hpp"

namespace frep {
namespace {
using namespace detail;

constexpr std::size_t kHeader = 84, kFacet = 50;

// True when the bytes look like ASCII STL: "solid" first, then a facet/endsolid keyword, and no
// NUL bytes early on (binary headers that begin with "solid" are followed by binary data).
bool looks_ascii(std::string_view b) {
  std::size_t i = 0;
  while (i < b.size() && (is_space(b[i]) || b[i] == '\n')) ++i;
  if (!istarts_with(b.substr(i), "solid")) return false;
  std::string_view head = b.substr(0, 4096);
  if (head.find('\0') != std::string_view::npos) return false;
  for (std::size_t k = 0; k < head.size(); ++k) {
    unsigned char c = static_cast<unsigned char>(head[k]);
    if (c < 9 || (c > 13 && c < 32)) return false;  // control bytes: binary payload
  }
  return true;
}

void check_finite(double v, const std::string& name, std::uint64_t line, std::uint64_t offset) {
  if (!std::isfinite(v))
    throw InputError(name, line, "vertex coordinate is not a finite number", offset);
}

TriMesh read_binary(std::string_view b, const std::string& name) {
  // Plain text that is not ASCII STL (another format named .stl): say so, not "truncated".
  const std::string_view head = b.substr(0, 4096);
  const bool text = std::all_of(head.begin(), head.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u >= 0x20 && u != 0x7f) || c == '\n' || c == '\r' || c == '\t';  // UTF-8 counts as text
  });
  if (text && !b.empty() && (b.size() < kHeader || kHeader + kFacet * std::uint64_t(load_u32le(b.data() + 80)) != b.size()))
    throw InputError(name, 0, "not an STL file: text that does not start with 'solid' (ASCII STL does; is it "
                              "another format with an .stl name?)");
  if (b.size() < kHeader)
    throw InputError(name, 0, "binary STL shorter than its 84-byte header (" + std::to_string(b.size()) +
                                  " bytes)", b.size());
  const std::uint64_t declared = load_u32le(b.data() + 80);
  const std::uint64_t body = b.size() - kHeader;
  std::uint64_t n = declared;
  TriMesh m;
  if (kHeader + kFacet * declared != b.size()) {
    if (body % kFacet == 0) {
      // The count field lies (some exporters write 0) or the file lost whole triangles at its
      // end: the size is consistent with whole facets, so read them all, and say so.
      n = body / kFacet;
      m.warnings.push_back("binary STL header declares " + std::to_string(declared) + " triangles but the file holds " +
                           std::to_string(n) + (n < declared ? " (truncated file?)" : "") + "; read " +
                           std::to_string(n));
    } else if (body / kFacet < declared) {
      throw InputError(name, 0,
                       "binary STL truncated: header declares " + std::to_string(declared) +
                           " triangles but the file ends inside triangle " + std::to_string(body / kFacet),
                       kHeader + kFacet * (body / kFacet));
    } else {
      // Trailing bytes after the declared facets (some exporters pad): ignored.
      m.warnings.push_back(std::to_string(body - kFacet * declared) + " bytes after the " + std::to_string(declared) +
                           " triangles the header declares were ignored");
    }
  }
  if (n == 0) throw InputError(name, 0, "binary STL has no triangles", 80);
  m.indexed = false;
  m.name = name;
  m.vertices.reserve(3 * n);
  m.triangles.reserve(n);
  m.origins.reserve(n);
  for (std::uint64_t t = 0; t < n; ++t) {
    const char* f = b.data() + kHeader + kFacet * t;
    for (int k = 0; k < 3; ++k) {
      Vec3 p;
      for (int c = 0; c < 3; ++c) {
        p[c] = load_f32le(f + 12 + 12 * k + 4 * c);
        check_finite(p[c], name, 0, kHeader + kFacet * t + 12 + 12 * k + 4 * c);
      }
      m.vertices.push_back(p);
    }
    const auto v = static_cast<std::uint32_t>(3 * t);
    m.add_triangle(v, v + 1, v + 2, static_cast<std::uint32_t>(t), 0);
  }
  return m;
}

TriMesh read_ascii(std::string_view b, const std::string& name) {
  TriMesh m;
  m.indexed = false;
  m.name = name;
  TokenCursor cur(b);
  std::string_view tok;
  std::uint32_t facet = 0;
  std::vector<Vec3> loop;
  auto expect = [&](std::string_view word) {
    if (!cur.next(tok))
      throw InputError(name, cur.line(), "ASCII STL ends early, expected '" + std::string(word) + "'");
    if (!iequals(tok, word))
      throw InputError(name, cur.line(),
                       "expected '" + std::string(word) + "', found '" + printable(tok) + "'");
  };
  bool in_solid = false;
  std::uint32_t polygons = 0;
  while (cur.next(tok)) {
    if (iequals(tok, "solid")) {
      cur.skip_line();  // the rest of the line is the solid's name
      in_solid = true;
      continue;
    }
    if (iequals(tok, "endsolid")) {
      cur.skip_line();  // the name here need not match the one after "solid"
      in_solid = false;
      continue;
    }
    if (!iequals(tok, "facet"))
      throw InputError(name, cur.line(), "expected 'facet' or 'endsolid', found '" + printable(tok) + "'");
    if (!in_solid && facet == 0)
      throw InputError(name, cur.line(), "ASCII STL facet before 'solid'");
    const std::uint64_t facet_line = cur.line();
    // "normal nx ny nz": the values are ignored (often zero or NaN); they need not even parse.
    expect("normal");
    for (int i = 0; i < 3; ++i)
      if (!cur.next(tok)) throw InputError(name, cur.line(), "ASCII STL ends inside a facet normal");
    expect("outer");
    expect("loop");
    loop.clear();
    for (;;) {
      if (!cur.next(tok)) throw InputError(name, cur.line(), "ASCII STL ends inside a facet loop");
      if (iequals(tok, "endloop")) break;
      if (!iequals(tok, "vertex"))
        throw InputError(name, cur.line(), "expected 'vertex' or 'endloop', found '" + printable(tok) + "'");
      Vec3 p;
      for (int c = 0; c < 3; ++c) {
        if (!cur.next(tok)) throw InputError(name, cur.line(), "ASCII STL ends inside a vertex");
        if (!parse_double(tok, p[c]))
          throw InputError(name, cur.line(), "bad vertex coordinate '" + printable(tok) + "'");
        check_finite(p[c], name, cur.line(), 0);
      }
      loop.push_back(p);
      if (loop.size() > 1000000)
        throw InputError(name, cur.line(), "facet loop with more than a million vertices");
    }
    expect("endfacet");
    if (loop.size() < 3)
      throw InputError(name, facet_line, "facet with " + std::to_string(loop.size()) + " vertices");
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (const Vec3& p : loop) m.vertices.push_back(p);
    polygons += loop.size() > 3;
    for (std::uint32_t k = 1; k + 1 < loop.size(); ++k)  // fan: polygons are not STL, but some writers emit them
      m.add_triangle(base, base + k, base + k + 1, facet, static_cast<std::uint32_t>(facet_line));
    ++facet;
  }
  if (m.triangles.empty()) throw InputError(name, cur.line(), "ASCII STL has no facets");
  if (in_solid) m.warnings.push_back("ASCII STL ends without 'endsolid' (truncated file?)");
  if (polygons > 0)
    m.warnings.push_back(std::to_string(polygons) + " facets have more than 3 vertices (not STL); they were split into triangles");
  return m;
}

}  // namespace

TriMesh read_stl(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw InputError(name, 0, "empty file");
  // A binary file whose size matches its triangle count is binary even if it starts with "solid".
  if (bytes.size() >= kHeader && kHeader + kFacet * std::uint64_t(load_u32le(bytes.data() + 80)) == bytes.size())
    return read_binary(bytes, name);
  if (looks_ascii(bytes)) return read_ascii(bytes, name);
  return read_binary(bytes, name);
}

}  // namespace frep
