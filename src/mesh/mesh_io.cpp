#include "frep/mesh/mesh_io.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "frep/error.hpp"
#include "frep/util/atomic_file.hpp"
#include "frep/util/text_scan.hpp"

namespace frep {
using namespace detail;

void TriMesh::check_consistent() const {
  if (!origins.empty() && origins.size() != triangles.size())
    throw InputError(name, 0, std::to_string(origins.size()) + " triangle origins for " +
                                  std::to_string(triangles.size()) + " triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::uint32_t v : triangles[t])
      if (v >= vertices.size())
        throw InputError(name, 0, "triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                                      " of " + std::to_string(vertices.size()));
}

void round_vertices_to_float(TriMesh& mesh) {
  // Over the coordinates as one flat array: GCC 12 at -O3 miscompiles the loop over Vec3s
  // (its vectorized epilogue rounds only z).
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  double* c = mesh.vertices.empty() ? nullptr : &mesh.vertices[0].x;
  const std::size_t n = 3 * mesh.vertices.size();
  for (std::size_t i = 0; i < n; ++i) c[i] = static_cast<double>(static_cast<float>(c[i]));
}

TriMesh compact_mesh(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles) {
  TriMesh out;
  constexpr std::uint32_t kUnused = 0xffffffffu;
  std::vector<std::uint32_t> id(vertices.size(), kUnused);
  for (const Triangle& tr : triangles)
    for (std::uint32_t v : tr) id[v] = 0;
  for (std::size_t v = 0; v < vertices.size(); ++v)
    if (id[v] != kUnused) {
      id[v] = static_cast<std::uint32_t>(out.vertices.size());
      out.vertices.push_back(vertices[v]);
    }
  for (const Triangle& tr : triangles) out.add_triangle(id[tr[0]], id[tr[1]], id[tr[2]]);
  return out;
}

Box3 bounding_box(const TriMesh& mesh) {
  Box3 b;
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) b.add(mesh.vertices[v]);
  if (b.empty())
    for (const Vec3& p : mesh.vertices) b.add(p);
  return b;
}

const char* format_name(MeshFormat f) {
  switch (f) {
    case MeshFormat::Stl: return "stl";
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Ply: return "ply";
    case MeshFormat::Off: return "off";
    case MeshFormat::ThreeMf: return "3mf";
    case MeshFormat::Unknown: break;
  }
  return "unknown";
}

MeshFormat format_from_extension(std::string_view path) {
  const auto dot = path.rfind('.');
  if (dot == std::string_view::npos) return MeshFormat::Unknown;
  const std::string_view ext = path.substr(dot + 1);
  if (iequals(ext, "stl")) return MeshFormat::Stl;
  if (iequals(ext, "obj")) return MeshFormat::Obj;
  if (iequals(ext, "ply")) return MeshFormat::Ply;
  if (iequals(ext, "off")) return MeshFormat::Off;
  if (iequals(ext, "3mf")) return MeshFormat::ThreeMf;
  return MeshFormat::Unknown;
}

MeshFormat sniff_format(std::string_view b) {
  if (b.substr(0, 4) == std::string_view("PK\x03\x04", 4)) return MeshFormat::ThreeMf;  // a zip: the one zipped mesh format
  if (b.size() >= 4 && b.substr(0, 3) == "ply" && (b[3] == '\n' || b[3] == '\r' || b[3] == ' ' || b[3] == '\t'))
    return MeshFormat::Ply;
  // A binary STL whose size matches its triangle count, whatever its header says.
  if (b.size() >= 84 && 84 + 50 * std::uint64_t(load_u32le(b.data() + 80)) == b.size()) return MeshFormat::Stl;
  std::size_t i = 0;
  while (i < b.size() && (is_space(b[i]) || b[i] == '\n')) ++i;
  const std::string_view t = b.substr(i);
  if (istarts_with(t, "solid")) return MeshFormat::Stl;
  // OFF keywords: OFF, COFF, NOFF, CNOFF, STOFF, ... followed by whitespace.
  {
    std::size_t k = 0;
    while (k < t.size() && k < 8 && !is_space(t[k]) && t[k] != '\n') ++k;
    const std::string_view kw = t.substr(0, k);
    if (kw.size() >= 3 && kw.substr(kw.size() - 3) == "OFF") return MeshFormat::Off;
  }
  // OBJ: the first statement is one of the usual OBJ keywords.
  LineCursor lines(b.substr(0, 65536));
  std::string_view line;
  while (lines.next(line)) {
    TokenSplitter ts(line);
    std::string_view kw;
    if (!ts.next(kw) || kw[0] == '#') continue;
    static const char* const obj_kw[] = {"v", "vt", "vn", "vp", "f", "g", "o", "s", "l", "p",
                                         "usemtl", "mtllib"};
    for (const char* k : obj_kw)
      if (kw == k) return MeshFormat::Obj;
    break;
  }
  return MeshFormat::Unknown;
}

TriMesh read_mesh_from_memory(std::string_view bytes, const std::string& name, const MeshReadOptions& options) {
  if (bytes.empty()) throw InputError(name, 0, "empty file");
  // Text files saved by some editors start with a UTF-8 byte order mark; a binary STL whose size
  // matches its triangle count keeps its header bytes, whatever they are.
  const bool binary_stl = bytes.size() >= 84 && 84 + 50 * std::uint64_t(load_u32le(bytes.data() + 80)) == bytes.size();
  if (!binary_stl && bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
  MeshFormat f = options.format;
  if (f == MeshFormat::Unknown) f = sniff_format(bytes);
  if (f == MeshFormat::Unknown) f = format_from_extension(name);
  switch (f) {
    case MeshFormat::Stl: return read_stl(bytes, name);
    case MeshFormat::Obj: return read_obj(bytes, name);
    case MeshFormat::Ply: return read_ply(bytes, name);
    case MeshFormat::Off: return read_off(bytes, name);
    case MeshFormat::ThreeMf: return read_3mf(bytes, name);
    case MeshFormat::Unknown: break;
  }
  if (const std::string ext = std::filesystem::path(name).extension().string(); ext == ".vm" || ext == ".rhai" || ext == ".frep")
    throw InputError(name, 0, "is an expression, not a mesh (expected STL, OBJ, PLY or OFF): commands that take "
                              "expressions read it (info, eval, render, mesh, sample...)");
  throw InputError(name, 0, "unrecognized mesh format (expected STL, OBJ, PLY, OFF or 3MF)");
}

TriMesh read_mesh(const std::string& path, const MeshReadOptions& options) {
  const std::string bytes = read_file(path);
  return read_mesh_from_memory(bytes, path, options);
}

namespace {

void put_u32(std::string& out, std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void put_f32(std::string& out, float v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void put_f64(std::string& out, double v) { out.append(reinterpret_cast<const char*>(&v), 8); }

Vec3 unit_normal(const TriMesh& m, std::size_t t) {
  Vec3 n = cross(m.corner(t, 1) - m.corner(t, 0), m.corner(t, 2) - m.corner(t, 0));
  const double l = length(n);
  return l > 0 && std::isfinite(l) ? n / l : Vec3{0, 0, 0};
}

}  // namespace

std::optional<LengthUnit> length_unit_from_name(std::string_view n) {
  if (iequals(n, "micron") || iequals(n, "um")) return LengthUnit::Micron;
  if (iequals(n, "mm") || iequals(n, "millimeter") || iequals(n, "millimetre")) return LengthUnit::Millimeter;
  if (iequals(n, "cm") || iequals(n, "centimeter") || iequals(n, "centimetre")) return LengthUnit::Centimeter;
  if (iequals(n, "inch") || iequals(n, "in")) return LengthUnit::Inch;
  if (iequals(n, "foot") || iequals(n, "ft")) return LengthUnit::Foot;
  if (iequals(n, "m") || iequals(n, "meter") || iequals(n, "metre")) return LengthUnit::Meter;
  return std::nullopt;
}

std::string write_mesh_to_string(const TriMesh& m, MeshFormat format, bool ascii, LengthUnit units) {
  std::string out;
  char buf[256];
  if (m.triangles.empty()) throw InputError(m.name, 0, "cannot write a mesh with no triangles");
  switch (format) {
    case MeshFormat::Stl:
      // STL stores single precision: refuse what would turn into infinities.
      for (std::size_t v = 0; v < m.vertices.size(); ++v)
        for (int c = 0; c < 3; ++c)
          if (!std::isfinite(static_cast<float>(m.vertices[v][c])))
            throw InputError(m.name, 0, "vertex " + std::to_string(v) +
                                            " is beyond single precision, which STL stores; write OBJ or PLY");
      if (ascii) {
        out += "solid frep\n";
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
          const Vec3 n = unit_normal(m, t);
          std::snprintf(buf, sizeof buf, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n.x, n.y, n.z);
          out += buf;
          for (int k = 0; k < 3; ++k) {
            const Vec3 p = m.corner(t, k);
            std::snprintf(buf, sizeof buf, "      vertex %.9g %.9g %.9g\n", double(float(p.x)), double(float(p.y)),
                          double(float(p.z)));
            out += buf;
          }
          out += "    endloop\n  endfacet\n";
        }
        out += "endsolid frep\n";
      } else {
        // The header must not begin with "solid", or naive readers take the file for ASCII.
        char header[80] = {};
        std::snprintf(header, sizeof header, "binary STL written by frep");
        out.append(header, 80);
        put_u32(out, static_cast<std::uint32_t>(m.triangles.size()));
        out.reserve(84 + 50 * m.triangles.size());
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
          const Vec3 n = unit_normal(m, t);
          put_f32(out, float(n.x)), put_f32(out, float(n.y)), put_f32(out, float(n.z));
          for (int k = 0; k < 3; ++k) {
            const Vec3 p = m.corner(t, k);
            put_f32(out, float(p.x)), put_f32(out, float(p.y)), put_f32(out, float(p.z));
          }
          out.append(2, '\0');
        }
      }
      return out;
    case MeshFormat::Obj:
      out += "# written by frep\n";
      for (const Vec3& p : m.vertices) {
        std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);  // exact round trip
        out += buf;
      }
      for (const Triangle& t : m.triangles) {
        std::snprintf(buf, sizeof buf, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
        out += buf;
      }
      return out;
    case MeshFormat::Ply:
      std::snprintf(buf, sizeof buf,
                    "ply\nformat binary_little_endian 1.0\ncomment written by frep\nelement vertex %zu\n"
                    "property double x\nproperty double y\nproperty double z\nelement face %zu\n"
                    "property list uchar uint vertex_indices\nend_header\n",
                    m.vertices.size(), m.triangles.size());
      out += buf;
      out.reserve(out.size() + 24 * m.vertices.size() + 13 * m.triangles.size());
      for (const Vec3& p : m.vertices) put_f64(out, p.x), put_f64(out, p.y), put_f64(out, p.z);
      for (const Triangle& t : m.triangles) {
        out.push_back(3);
        for (std::uint32_t v : t) put_u32(out, v);
      }
      return out;
    case MeshFormat::ThreeMf:
      return write_3mf(m, units);
    case MeshFormat::Off:
    case MeshFormat::Unknown:
      break;
  }
  throw InputError("", 0, std::string("cannot write meshes as ") + format_name(format) + " (use stl, obj, ply or 3mf)");
}

void write_mesh(const std::string& path, const TriMesh& mesh, const MeshWriteOptions& options) {
  MeshFormat f = options.format == MeshFormat::Unknown ? format_from_extension(path) : options.format;
  if (f == MeshFormat::Unknown && is_device(path)) f = MeshFormat::Stl;  // /dev/null: binary STL, in place
  if (f == MeshFormat::Unknown || f == MeshFormat::Off)
    throw InputError(path, 0, "cannot tell the output mesh format; use a .stl, .obj, .ply or .3mf name");
  write_file_atomically(path, write_mesh_to_string(mesh, f, options.ascii, options.units));
}

}  // namespace frep
