// STL reader: ASCII and binary, told apart by content rather than by the "solid" prefix that
// many binary exporters put in their header.
#include <algorithm>
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "frep/util/text_scan.hpp"

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

// "1 facet normal is" / "3 facet normals are".
std::string count_of(std::uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Spellings of NaN and infinity that C libraries print and from_chars does not take: "-nan",
// "nan(ind)", MSVC's "1.#QNAN0", "-1.#IND00", "1.#INF00".
bool spells_non_finite(std::string_view tok) {
  std::string low;
  for (char c : tok.substr(0, 32)) low += lower(c);
  return low.find("nan") != std::string::npos || low.find("inf") != std::string::npos ||
         low.find("#ind") != std::string::npos;
}

// What a tolerated oddity of ASCII STL looks like in the warning: how many, and the first line.
struct Oddity {
  std::uint64_t count = 0, first_line = 0;
  std::string first_text;
  void note(std::uint64_t line, std::string_view text = {}) {
    if (count++ == 0) first_line = line, first_text = printable(text);
  }
};

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
  std::uint64_t bad_normals = 0, first_bad = 0;
  for (std::uint64_t t = 0; t < n; ++t) {
    const char* f = b.data() + kHeader + kFacet * t;
    // The normal is never used (exporters write zero, NaN or stale ones): a NaN or infinite one
    // is only reported.
    bool finite_normal = true;
    for (int c = 0; c < 3; ++c) finite_normal = finite_normal && std::isfinite(load_f32le(f + 4 * c));
    if (!finite_normal && bad_normals++ == 0) first_bad = t;
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
  if (bad_normals > 0)
    m.warnings.push_back(count_of(bad_normals, "facet normal is", "facet normals are") +
                         " NaN or infinite (the first in triangle " + std::to_string(first_bad) + ", byte " +
                         std::to_string(kHeader + kFacet * first_bad) + "); normals are not used, so they were ignored");
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
  Oddity garbage_normals, non_finite_normals, trailing_words;
  // Some writers (G-code tools among them) put words after "endloop" or "endfacet" on the same
  // line; slicers ignore them, and so does this, unless they are the next keyword (a file that
  // keeps several keywords on one line).
  auto skip_trailing_words = [&](const char* next, const char* or_next) {
    if (!cur.more_on_line()) return;
    TokenCursor peek = cur;
    std::string_view word;
    const std::uint64_t line = cur.line();
    if (peek.next(word) && (iequals(word, next) || (or_next && iequals(word, or_next)))) return;
    trailing_words.note(line, word);
    cur.skip_line();
  };
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
    // "normal nx ny nz": never used, so read as slicers do: whatever stands before "outer loop"
    // (zero, NaN, "1.#QNAN", a missing or partial normal) is skipped; what is not a finite
    // normal is reported once per kind.
    {
      std::string_view words[4];
      std::size_t count = 0;
      for (;;) {
        if (!cur.next(tok)) throw InputError(name, cur.line(), "ASCII STL ends inside a facet normal");
        if (iequals(tok, "outer")) break;
        if (count >= 16 || iequals(tok, "vertex") || iequals(tok, "loop") || iequals(tok, "endloop") ||
            iequals(tok, "endfacet") || iequals(tok, "facet") || iequals(tok, "endsolid") || iequals(tok, "solid"))
          throw InputError(name, cur.line(), "expected 'outer loop', found '" + printable(tok) + "'");
        if (count < 4) words[count] = tok;
        ++count;
      }
      bool readable = count == 4 && iequals(words[0], "normal"), finite = true;
      for (std::size_t i = 1; readable && i < 4; ++i) {
        double v;
        if (parse_double(words[i], v)) finite = finite && std::isfinite(v);
        else if (spells_non_finite(words[i])) finite = false;
        else readable = false;
      }
      if (!readable) {
        std::string text = "facet";
        for (std::size_t i = 0; i < std::min<std::size_t>(count, 4); ++i) text += " " + std::string(words[i]);
        if (count > 4) text += " ...";
        garbage_normals.note(facet_line, text);
      } else if (!finite) {
        non_finite_normals.note(facet_line);
      }
    }
    expect("loop");
    loop.clear();
    for (;;) {
      if (!cur.next(tok)) throw InputError(name, cur.line(), "ASCII STL ends inside a facet loop");
      if (iequals(tok, "endloop")) {
        skip_trailing_words("endfacet", nullptr);
        break;
      }
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
    skip_trailing_words("facet", "endsolid");
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
  if (trailing_words.count > 0)
    m.warnings.push_back(count_of(trailing_words.count, "line has", "lines have") +
                         " words after 'endloop' or 'endfacet' (the first, line " +
                         std::to_string(trailing_words.first_line) + ": '" + trailing_words.first_text +
                         "'); they were ignored");
  if (non_finite_normals.count > 0)
    m.warnings.push_back(count_of(non_finite_normals.count, "facet normal is", "facet normals are") +
                         " NaN or infinite (the first on line " + std::to_string(non_finite_normals.first_line) +
                         "); normals are not used, so they were ignored");
  if (garbage_normals.count > 0)
    m.warnings.push_back(count_of(garbage_normals.count, "facet has", "facets have") +
                         " no readable 'normal nx ny nz' (the first on line " +
                         std::to_string(garbage_normals.first_line) + ": '" + garbage_normals.first_text +
                         "'); normals are not used, so they were ignored");
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
