// PLY reader: ASCII and binary (little and big endian), any property order, polygon faces
// ("vertex_indices" or "vertex_index") and triangle strips; other elements are skipped.
#include <bit>
#include <cmath>
#include <vector>

#include "frep/mesh/mesh_io.hpp"
#include "frep/util/text_scan.hpp"

namespace frep {
namespace {
using namespace detail;

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parse_type(std::string_view s, Type& t) {
  static const struct { const char* name; Type type; } names[] = {
      {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
      {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
      {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
      {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
  for (const auto& n : names)
    if (s == n.name) {
      t = n.type;
      return true;
    }
  return false;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 1;
}

bool is_integer(Type t) { return t != Type::F32 && t != Type::F64; }

const char* type_name(Type t) {
  switch (t) {
    case Type::I8: return "char";
    case Type::U8: return "uchar";
    case Type::I16: return "short";
    case Type::U16: return "ushort";
    case Type::I32: return "int";
    case Type::U32: return "uint";
    case Type::F32: return "float";
    case Type::F64: return "double";
  }
  return "?";
}

// Whether an ASCII integer is in the range of its declared type (binary values always are).
bool fits(Type t, std::int64_t v) {
  switch (t) {
    case Type::I8: return v >= -128 && v <= 127;
    case Type::U8: return v >= 0 && v <= 255;
    case Type::I16: return v >= -32768 && v <= 32767;
    case Type::U16: return v >= 0 && v <= 65535;
    case Type::I32: return v >= INT32_MIN && v <= INT32_MAX;
    case Type::U32: return v >= 0 && v <= UINT32_MAX;
    default: return true;
  }
}

struct Property {
  std::string name;
  Type type = Type::F32;
  bool is_list = false;
  Type count_type = Type::U8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  std::uint64_t line = 0;
};

enum class Encoding { Ascii, BinaryLE, BinaryBE };

// Reads values from the body, ASCII tokens or binary, always bounds-checked.
class Reader {
 public:
  Reader(std::string_view bytes, std::size_t start, std::uint64_t start_line, Encoding enc,
         const std::string& name)
      : b_(bytes), pos_(start), enc_(enc), name_(name), tokens_(bytes, start, start_line) {}

  double value(Type t) {
    if (enc_ == Encoding::Ascii) {
      std::string_view tok;
      if (!tokens_.next(tok)) fail_end();
      if (is_integer(t)) {
        std::int64_t i;
        if (!parse_int(tok, i)) throw InputError(name_, tokens_.line(), "bad integer '" + printable(tok) + "'");
        if (!fits(t, i))
          throw InputError(name_, tokens_.line(), "integer " + printable(tok) + " does not fit the property's type " + type_name(t));
        return static_cast<double>(i);
      }
      double d;
      if (!parse_double(tok, d)) throw InputError(name_, tokens_.line(), "bad number '" + printable(tok) + "'");
      return d;
    }
    const std::size_t n = type_size(t);
    if (b_.size() - pos_ < n) fail_end();
    unsigned char buf[8];
    std::memcpy(buf, b_.data() + pos_, n);
    if (enc_ == Encoding::BinaryBE)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(buf[i], buf[n - 1 - i]);
    pos_ += n;
    switch (t) {
      case Type::I8: { std::int8_t v; std::memcpy(&v, buf, 1); return v; }
      case Type::U8: return buf[0];
      case Type::I16: { std::int16_t v; std::memcpy(&v, buf, 2); return v; }
      case Type::U16: { std::uint16_t v; std::memcpy(&v, buf, 2); return v; }
      case Type::I32: { std::int32_t v; std::memcpy(&v, buf, 4); return v; }
      case Type::U32: { std::uint32_t v; std::memcpy(&v, buf, 4); return v; }
      case Type::F32: { float v; std::memcpy(&v, buf, 4); return v; }
      case Type::F64: { double v; std::memcpy(&v, buf, 8); return v; }
    }
    return 0;
  }

  // Where the value about to be read sits: a line (ASCII) or a byte offset (binary).
  std::uint64_t line() const { return enc_ == Encoding::Ascii ? tokens_.line() : 0; }
  std::uint64_t offset() const { return enc_ == Encoding::Ascii ? 0 : pos_; }
  std::size_t remaining() const {
    return b_.size() - (enc_ == Encoding::Ascii ? std::min(tokens_.pos(), b_.size()) : pos_);
  }
  [[noreturn]] void fail(const std::string& msg) const { throw InputError(name_, line(), msg, offset()); }

  // ASCII PLY writes each entry of an element on a line of its own: check that the entry just
  // read, which began on line `first`, neither ran onto another line nor left values behind, so
  // that a miscounted line is reported where it is instead of shifting everything after it.
  void end_entry(std::uint64_t first, const std::string& element) const {
    if (enc_ != Encoding::Ascii) return;
    if (tokens_.line() != first)
      throw InputError(name_, first, "entry of element '" + printable(element) + "' has fewer values than its " +
                                         "properties declare (it runs on to line " + std::to_string(tokens_.line()) + ")");
    if (tokens_.more_on_line())
      throw InputError(name_, first, "entry of element '" + printable(element) + "' has more values than its properties declare");
  }
  // The line the next value is on (ASCII), found without consuming it.
  std::uint64_t next_line() const {
    if (enc_ != Encoding::Ascii) return 0;
    TokenCursor peek = tokens_;
    std::string_view tok;
    return peek.next(tok) ? peek.line() : tokens_.line();
  }
  [[noreturn]] void fail_end() const {
    throw InputError(name_, line(), "PLY data ends early (truncated file?)", enc_ == Encoding::Ascii ? 0 : pos_);
  }

 private:
  std::string_view b_;
  std::size_t pos_;
  Encoding enc_;
  const std::string& name_;
  TokenCursor tokens_;
};

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::uint64_t list_length(Reader& r, Type count_type) {
  const double n = r.value(count_type);
  if (!(n >= 0) || n > 4294967295.0) r.fail("bad list length " + std::to_string(n));
  return static_cast<std::uint64_t>(n);
}

}  // namespace

TriMesh read_ply(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw InputError(name, 0, "empty file");
  LineCursor lines(bytes);
  std::string_view line;
  if (!lines.next(line)) throw InputError(name, 1, "not a PLY file (first line must be 'ply')");
  while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  if (line != "ply") throw InputError(name, 1, "not a PLY file (first line must be 'ply')");
  Encoding enc = Encoding::Ascii;
  bool have_format = false, ended = false;
  std::vector<Element> elements;
  while (lines.next(line)) {
    const std::uint64_t ln = lines.line_no();
    TokenSplitter t(line);
    std::string_view kw;
    if (!t.next(kw)) continue;
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") {
      ended = true;
      break;
    }
    if (kw == "format") {
      std::string_view f;
      t.next(f);
      if (f == "ascii") enc = Encoding::Ascii;
      else if (f == "binary_little_endian") enc = Encoding::BinaryLE;
      else if (f == "binary_big_endian") enc = Encoding::BinaryBE;
      else throw InputError(name, ln, "unknown PLY format '" + printable(f) + "'");
      std::string_view version;
      if (!t.next(version) || version != "1.0")
        throw InputError(name, ln, "PLY format version '" + printable(version) + "' is not supported (only 1.0)");
      have_format = true;
    } else if (kw == "element") {
      Element e;
      std::string_view n, c;
      std::int64_t count;
      if (!t.next(n) || !t.next(c) || !parse_int(c, count) || count < 0)
        throw InputError(name, ln, "bad element line (expected 'element NAME COUNT')");
      e.name = std::string(n);
      e.count = static_cast<std::uint64_t>(count);
      e.line = ln;
      elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (elements.empty()) throw InputError(name, ln, "property before any element");
      Property p;
      std::string_view ty, n;
      if (!t.next(ty)) throw InputError(name, ln, "bad property line");
      if (ty == "list") {
        std::string_view ct, it;
        if (!t.next(ct) || !t.next(it) || !parse_type(ct, p.count_type) || !parse_type(it, p.type) ||
            !is_integer(p.count_type))
          throw InputError(name, ln, "bad list property (expected 'property list COUNT_TYPE ITEM_TYPE NAME')");
        p.is_list = true;
      } else if (!parse_type(ty, p.type)) {
        throw InputError(name, ln, "unknown property type '" + printable(ty) + "'");
      }
      if (!t.next(n)) throw InputError(name, ln, "property without a name");
      p.name = std::string(n);
      elements.back().props.push_back(std::move(p));
    } else {
      throw InputError(name, ln, "unknown PLY header line '" + printable(kw) + "'");
    }
    if (lines.line_no() > 100000) throw InputError(name, ln, "PLY header longer than 100000 lines");
  }
  if (!ended) throw InputError(name, lines.line_no(), "PLY header has no 'end_header'");
  if (!have_format) throw InputError(name, lines.line_no(), "PLY header has no 'format' line");

  const std::size_t body = lines.pos();
  Reader r(bytes, std::min(body, bytes.size()), lines.line_no() + 1, enc, name);

  // The vertex count bounds every face index, and is known before any data is read.
  std::uint64_t nverts = 0;
  bool have_vertices = false;
  for (const Element& e : elements)
    if (e.name == "vertex") {
      nverts = e.count;
      have_vertices = true;
    }
  if (!have_vertices) throw InputError(name, 0, "PLY file has no 'vertex' element");

  TriMesh m;
  m.name = name;
  std::uint32_t face = 0;
  std::vector<std::uint32_t> poly;
  for (const Element& e : elements) {
    // Check the declared count against the bytes present before allocating or looping.
    std::uint64_t min_bytes = 0;
    for (const Property& p : e.props)
      min_bytes += enc == Encoding::Ascii ? 2 : type_size(p.is_list ? p.count_type : p.type);
    if (e.count > 0 && e.props.empty())
      throw InputError(name, e.line, "element '" + printable(e.name) + "' has no properties");
    if (e.count > 0 && (r.remaining() + 1) / min_bytes < e.count)
      throw InputError(name, e.line,
                       "element '" + printable(e.name) + "' declares " + std::to_string(e.count) +
                           " entries but the file has only " + std::to_string(r.remaining()) +
                           " bytes of data left");
    if (e.name == "vertex") {
      if (e.count >= 0xffffffffu) throw InputError(name, e.line, "too many vertices");
      int axis[3] = {-1, -1, -1};
      for (std::size_t i = 0; i < e.props.size(); ++i)
        for (int c = 0; c < 3; ++c)
          if (e.props[i].name == std::string(1, char('x' + c)) && !e.props[i].is_list) axis[c] = int(i);
      for (int c = 0; c < 3; ++c)
        if (axis[c] < 0)
          throw InputError(name, e.line, std::string("vertex element has no '") + char('x' + c) + "' property");
      m.vertices.reserve(e.count);
      for (std::uint64_t v = 0; v < e.count; ++v) {
        const std::uint64_t first = r.next_line();
        Vec3 p;
        for (std::size_t i = 0; i < e.props.size(); ++i) {
          const Property& pr = e.props[i];
          if (pr.is_list) {
            const std::uint64_t n = list_length(r, pr.count_type);
            for (std::uint64_t k = 0; k < n; ++k) r.value(pr.type);
            continue;
          }
          const std::uint64_t off = r.offset();  // binary: where the value starts
          const double val = r.value(pr.type);
          const std::uint64_t ln = r.line();  // ASCII: the line of the token just read
          for (int c = 0; c < 3; ++c)
            if (axis[c] == int(i)) {
              if (!std::isfinite(val)) throw InputError(name, ln, "vertex coordinate is not a finite number", off);
              p[c] = val;
            }
        }
        r.end_entry(first, e.name);
        m.vertices.push_back(p);
      }
    } else if (e.name == "face" || e.name == "tristrips") {
      const bool strips = e.name == "tristrips";
      int idx = -1;
      for (std::size_t i = 0; i < e.props.size(); ++i)
        if (e.props[i].is_list && (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index"))
          idx = int(i);
      if (idx < 0) throw InputError(name, e.line, "element '" + e.name + "' has no 'vertex_indices' list");
      for (std::uint64_t f = 0; f < e.count; ++f) {
        const std::uint64_t first = r.next_line();
        for (std::size_t i = 0; i < e.props.size(); ++i) {
          const Property& pr = e.props[i];
          if (!pr.is_list) {
            r.value(pr.type);
            continue;
          }
          const std::uint64_t ln = first;  // ASCII: the entry's line (end_entry checks it is one line)
          const std::uint64_t n = list_length(r, pr.count_type);
          if (enc != Encoding::Ascii && n * type_size(pr.type) > r.remaining()) r.fail_end();
          if (int(i) != idx) {
            for (std::uint64_t k = 0; k < n; ++k) r.value(pr.type);
            continue;
          }
          poly.clear();
          auto flush_strip = [&] {
            for (std::size_t k = 0; k + 2 < poly.size(); ++k) {
              std::uint32_t a = poly[k], b = poly[k + 1], c = poly[k + 2];
              if (a == b || b == c || a == c) continue;  // joining triangles of a strip
              if (k % 2) std::swap(a, b);                // every other triangle is reversed
              m.add_triangle(a, b, c, face, static_cast<std::uint32_t>(ln));
            }
            poly.clear();
          };
          for (std::uint64_t k = 0; k < n; ++k) {
            const std::uint64_t voff = r.offset();
            const double v = r.value(pr.type);
            const std::uint64_t vln = r.line();
            // A strip restarts at -1, which an unsigned index type stores as its maximum.
            if (strips && (v == -1 || v == 4294967295.0 || (type_size(pr.type) == 2 && v == 65535.0))) {
              flush_strip();
              continue;
            }
            if (!(v >= 0) || v >= double(nverts) || v != std::floor(v))
              throw InputError(name, vln,
                               "face " + std::to_string(face) + " refers to vertex " + number_text(v) +
                                   " but there are " + std::to_string(nverts) + " vertices",
                               voff);
            poly.push_back(static_cast<std::uint32_t>(v));
          }
          if (strips) {
            flush_strip();
          } else {
            if (poly.size() < 3)
              throw InputError(name, ln, "face " + std::to_string(face) + " has " + std::to_string(poly.size()) +
                                             " vertex indices (a face needs at least 3)", r.offset());
            for (std::size_t k = 1; k + 1 < poly.size(); ++k)
              m.add_triangle(poly[0], poly[k], poly[k + 1], face, static_cast<std::uint32_t>(ln));
          }
          ++face;
        }
        r.end_entry(first, e.name);
      }
    } else {
      for (std::uint64_t f = 0; f < e.count; ++f) {
        const std::uint64_t first = r.next_line();
        for (const Property& pr : e.props) {
          const std::uint64_t n = pr.is_list ? list_length(r, pr.count_type) : 1;
          if (enc != Encoding::Ascii && n * type_size(pr.type) > r.remaining()) r.fail_end();
          for (std::uint64_t k = 0; k < n; ++k) r.value(pr.type);
        }
        r.end_entry(first, e.name);
      }
    }
  }
  if (m.triangles.empty()) throw InputError(name, 0, "PLY file has no faces");
  return m;
}

}  // namespace frep
