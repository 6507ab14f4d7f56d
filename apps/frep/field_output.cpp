// Output of the field-transforming commands (field_output.hpp).
#include "field_output.hpp"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "input.hpp"
#include "frep/contour/bounds.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/script/save.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace frep::cli {
namespace {

std::string fmt_point(const Vec3& p) { return fmt::format("{:.6g}, {:.6g}, {:.6g}", p.x, p.y, p.z); }

}  // namespace

bool is_mesh_output(const std::string& path) {
  if (is_device(path)) return true;  // /dev/null: a binary STL, as write_mesh writes there
  const MeshFormat f = format_from_extension(path);
  return f == MeshFormat::Stl || f == MeshFormat::Obj || f == MeshFormat::Ply || f == MeshFormat::ThreeMf;
}

void add_field_output_options(CLI::App* cmd, const std::shared_ptr<FieldOutputOptions>& o) {
  cmd->add_option("--resolution,-r", o->resolution, "Cells across the longest side of the region meshed (mesh output)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            int v = 0;
            if (!CLI::detail::lexical_cast(s, v) || v < 1 || v > kMaxMeshResolution)
              return "the resolution must be a whole number from 1 to " + std::to_string(kMaxMeshResolution) +
                     " (cells along an axis), got " + s;
            return {};
          },
          "1.." + std::to_string(kMaxMeshResolution)))
      ->capture_default_str();
  cmd->add_option("--bounds", o->bounds,
                  "Region to mesh, x0,y0,z0,x1,y1,z1 (default: the input's bounding box grown by what the operation "
                  "adds; a shape reaching given bounds is cut and closed there)")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--threads,-j", o->threads, "Worker threads (0 = all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_flag("--quiet,-q", o->quiet, "Print nothing but errors");
  add_repair_option(cmd, o->repair);
  add_lipschitz_option(cmd, o->lipschitz);
  add_units_option(cmd, o->units);
  add_max_error_option(cmd, o->max_error);
}

void check_field_output_options(const FieldOutputOptions& o) {
  if (!o.bounds.empty()) bounds_option(o.bounds);
}

void check_field_output(const std::string& path, const std::string& input) {
  if (!is_mesh_output(path)) {
    const MeshFormat f = format_from_extension(path);
    if (f != MeshFormat::Unknown)
      throw InputError(path, 0, std::string("cannot write .") + format_name(f) +
                                    ": the output is a mesh (.stl, .obj, .ply, .3mf) or an expression (.vm, .rhai, .frep)");
    try {
      check_expression_path(path);
    } catch (const InputError&) {
      throw InputError(path, 0, "unknown output format: use .stl, .obj, .ply or .3mf (a mesh) or .vm, .rhai or .frep (the expression)");
    }
  }
  check_output(path, {input});
}

Box3 input_region(const std::string& input, const FieldInfo& info, const Tape& tape, const FieldOutputOptions& o) {
  if (!o.bounds.empty())
    return Box3{{o.bounds[0], o.bounds[1], o.bounds[2]}, {o.bounds[3], o.bounds[4], o.bounds[5]}};
  BoundsSearchOptions bs;
  bs.threads = o.threads;
  bs.lipschitz = std::max(0.0, o.lipschitz);
  try {
    return field_region(tape, info, bs);
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    throw InputError(input, 0, e.detail());
  }
}

FieldInfo output_facts(const Field& result, const Model& input, double reach, bool mesh_out, std::optional<Tape>& tape) {
  FieldInfo info = result.info;
  const bool check = info.bounds.empty() && !input.info.bounds.empty();
  if (mesh_out || check) tape = Tape::compile(result.graph(), result.id());
  if (check) info.bounds = checked_bounds(*tape, input.info.bounds.inflated(std::max(reach, 0.0)));
  return info;
}

void write_field_output(const std::string& input, const std::string& path, const Graph& g, NodeId root,
                        const Box3& region, const FieldOutputOptions& o, const FieldInfo& info, const Tape* tape) {
  if (!is_mesh_output(path)) {
    save_expression(path, g, root, info, &mesh_oracle_codec());
    if (!o.quiet) fmt::print("wrote {} (the expression)\n", path);
    return;
  }
  MeshOptions mo;
  mo.method = MeshMethod::DualContouring;
  mo.resolution = o.resolution;
  mo.threads = o.threads;
  mo.lipschitz = std::max(0.0, o.lipschitz);
  apply_max_error(o.max_error, mo);
  if (!o.bounds.empty())
    mo.bounds = region;  // exactly as given: cut and capped where the shape reaches it
  else
    mo.known_bounds = region;
  MeshStats st;
  TriMesh mesh;
  try {
    mesh = tape ? mesh_expression(*tape, mo, &st) : mesh_expression(Tape::compile(g, root), mo, &st);
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    throw InputError(input, 0, e.detail());
  }
  if (mesh.triangles.empty())
    throw InputError(input, 0,
                     "the result is empty: no sample of the grid is inside it (the operation removed everything, "
                     "or it is thinner than a cell: try a finer --resolution)");
  write_mesh_output(path, mesh, o.units);
  warn_unresolved(st.unresolved);
  if (!o.quiet) {
    fmt::print("grid: {} x {} x {} cells of {:.6g} over {} .. {}\n", st.cells[0], st.cells[1], st.cells[2],
               st.cell_size, fmt_point(st.bounds.lo), fmt_point(st.bounds.hi));
    if (st.capped) fmt::print("note: the shape reaches the bounds; it is cut there and closed with flat caps\n");
    print_mesh_notes(st);
    fmt::print("mesh: {} triangles, {} vertices (dual contouring)\n", mesh.triangles.size(), mesh.vertices.size());
    fmt::print("wrote {}\n", path);
  }
}

}  // namespace frep::cli
