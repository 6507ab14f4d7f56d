#include "input.hpp"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "frep/convert/convert.hpp"
#include "frep/script/load.hpp"
#include "frep/convert/make_solid.hpp"
#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::cli {

Model load_input(const std::string& path, bool quiet, ConvertStats* stats, bool repair) {
  ConvertStats s;
  ConvertOptions o;
  o.repair = repair;
  Model m = load_field(path, o, &s);
  if (stats) *stats = s;
  print_read_warnings(path, s.read_warnings);
  if (!s.repaired.empty()) fmt::print(stderr, "frep: repaired {}: {}\n", path, s.repaired);
  if (s.triangles > 0 && !quiet)
    fmt::print(stderr, "frep: read {} ({} triangles, checked and indexed in {:.2f} s)\n", path, s.triangles, s.seconds);
  return m;
}

void add_repair_option(CLI::App* cmd, bool& value) {
  cmd->add_flag("--repair", value,
                "Repair a mesh that is not a valid solid first (as frep repair does) instead of refusing it");
}

void add_units_option(CLI::App* cmd, std::string& value) {
  cmd->add_option("--units", value, "Length unit of a .3mf output's coordinates: micron, mm, cm, inch, foot or m")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            return length_unit_from_name(s) ? std::string() : "unknown unit " + s + ": use micron, mm, cm, inch, foot or m";
          },
          "UNIT"))
      ->capture_default_str();
}

void write_mesh_output(const std::string& path, const TriMesh& mesh, const std::string& units) {
  MeshWriteOptions o;
  o.units = length_unit_from_name(units).value_or(LengthUnit::Millimeter);
  if (format_from_extension(path) != MeshFormat::ThreeMf) return write_mesh(path, mesh, o);
  // Serialized once: what is checked is read back from the very bytes that are written.
  const std::string bytes = write_3mf(mesh, o.units);
  const ValidationReport stored = validate_mesh(read_3mf(bytes, path));
  if (!stored.is_solid() && validate_mesh(mesh).is_solid())
    throw InputError(path, 0, "3MF keeps six decimals of each coordinate, and the mesh rounded so is no longer a valid solid (" +
                                  stored.summary() + "): write .stl, .obj or .ply, or give coordinates in smaller units");
  write_file_atomically(path, bytes);
}

TriMesh repaired_if_asked(TriMesh mesh, bool repair, bool quiet, std::string* summary) {
  if (!repair) return mesh;
  RepairOptions ro;
  ro.quiet = quiet;
  RepairResult r = make_solid(mesh, ro);
  if (summary) *summary = repair_summary(r.report);
  if (r.report.changed) fmt::print(stderr, "frep: repaired {}: {}\n", mesh.name, repair_summary(r.report));
  r.mesh.name = mesh.name;
  return std::move(r.mesh);
}

void check_output(const std::string& output, std::initializer_list<std::string> inputs) {
  check_output_directory(output);
  std::error_code ec;
  for (const std::string& in : inputs)
    if (std::filesystem::equivalent(output, in, ec))
      throw InputError(output, 0, "is the input file " + in + ": writing it would replace the input; choose another output name");
}

void print_read_warnings(const std::string& path, const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) fmt::print(stderr, "frep: warning: {}: {}\n", path, w);
}

TriMesh read_mesh_noting(const std::string& path) {
  TriMesh mesh = read_mesh(path);
  print_read_warnings(path, mesh.warnings);
  return mesh;
}

void warn_unresolved(std::size_t unresolved) {
  if (unresolved == 0) return;
  fmt::print(stderr,
             "frep: warning: {} vertices could not be untangled: the mesh is closed and manifold, but its triangles "
             "cross there (frep check shows where); another --resolution usually avoids it\n",
             unresolved);
}

void note_if_not_a_distance(const char* command, const std::string& input, const Model& m, bool quiet) {
  if (quiet || m.info.lipschitz == 1) return;
  fmt::print(stderr,
             "frep {}: note: {} does not say it is a distance field (meshes and frep convert's files do); on "
             "other fields the result is not at the distance given\n",
             command, input);
}

void print_mesh_notes(const MeshStats& st) {
  if (st.zero_corners > 0)
    fmt::print("note: {} grid corners were exactly on the surface (faces on grid planes); meshed again on a grid "
               "shifted by 1/64 of a cell\n",
               st.zero_corners);
  if (st.unresolved_first > 0)
    fmt::print("note: {} vertices of the first grid could not be untangled; meshed again on shifted grids ({} left)\n",
               st.unresolved_first, st.unresolved);
  if (st.simplify_rejected)
    fmt::print("note: the simplified mesh failed validation; the uniform mesh of the grid is written\n");
  else if (st.triangles_before_simplify > 0 && st.max_error > 0)
    fmt::print("simplified {} -> {} triangles within {:.3g} in {:.2f} s\n", st.triangles_before_simplify,
               st.triangles, st.max_error, st.seconds_simplify);
  else if (st.triangles_before_simplify > st.triangles)
    fmt::print("merged flat regions: {} -> {} triangles in {:.2f} s (--max-error 0: the uniform mesh)\n",
               st.triangles_before_simplify, st.triangles, st.seconds_simplify);
}

void add_max_error_option(CLI::App* cmd, std::string& value) {
  value = kDefaultMaxError;
  cmd->add_option("--max-error", value,
                  "flat: merge the triangles of flat regions only (the surface keeps its points); E or Nc: simplify "
                  "while every triangle stays within this |f| of the surface (sampled), in model units or N cells "
                  "(0.05c: a twentieth of a cell, invisible; 0.5c for scans); 0: the uniform mesh of the grid")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            MeshOptions o;
            if (!frep::set_max_error(o, s))
              return "the maximum error must be flat or a number >= 0, in model units or followed by c (cells), got " + s;
            return {};
          },
          "flat, E or Nc"))
      ->capture_default_str();
}

void apply_max_error(const std::string& value, MeshOptions& o) {
  if (!frep::set_max_error(o, value)) throw CLI::ValidationError("--max-error", "not flat nor a number >= 0: " + value);
}

Box3 bounds_option(const std::vector<double>& b) {
  if (b.size() != 6) throw CLI::ValidationError("--bounds", "expected six numbers: x0,y0,z0,x1,y1,z1");
  for (double v : b)
    if (!std::isfinite(v)) throw CLI::ValidationError("--bounds", "the bounds must be finite numbers");
  for (int i = 0; i < 3; ++i)
    if (!(b[static_cast<std::size_t>(i)] < b[static_cast<std::size_t>(i) + 3]))
      throw CLI::ValidationError("--bounds", fmt::format("the bounds are empty along {}: need {}0 < {}1", "xyz"[i], "xyz"[i], "xyz"[i]));
  return Box3{{b[0], b[1], b[2]}, {b[3], b[4], b[5]}};
}

void add_lipschitz_option(CLI::App* cmd, double& value) {
  value = -1;
  cmd->add_option("--lipschitz", value,
                  "Assume |f(p) - f(q)| <= L |p - q| (1 for exact distances): boxes then settle from the value at their "
                  "centre, much faster on converted meshes. Default: what the input says (1 for meshes and for files "
                  "frep convert wrote), else unknown; 0 turns it off. A wrong L gives wrong pictures and meshes")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v) || v < 0)
              return "the Lipschitz bound must be a finite number >= 0, got " + s;
            return {};
          },
          "L >= 0"));
}

}  // namespace frep::cli
