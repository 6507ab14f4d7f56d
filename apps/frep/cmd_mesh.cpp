// frep mesh: an expression to a closed, manifold triangle mesh (dual contouring or snap).
#include <fmt/core.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "input.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/error.hpp"
#include "frep/script/load.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace frep::cli {
namespace {

void check_output_path(const std::string& path, const std::string& input) {
  const MeshFormat f = format_from_extension(path);
  if (f != MeshFormat::Stl && f != MeshFormat::Obj && f != MeshFormat::Ply && f != MeshFormat::ThreeMf && !is_device(path))
    throw InputError(path, 0, "unknown mesh format for the output: use a .stl, .obj, .ply or .3mf file name");
  check_output(path, {input});
}

std::string fmt_point(const Vec3& p) { return fmt::format("{:.6g}, {:.6g}, {:.6g}", p.x, p.y, p.z); }

}  // namespace

void register_mesh(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "mesh", "Mesh an expression: a closed, manifold, outward-oriented triangle mesh of where it is negative");
  struct Args {
    std::string input, output, method = "dc", gradient = "analytic", units = "mm";
    int resolution = 0;
    double cell = 0;
    std::vector<double> bounds;
    int threads = 0, snap_iterations = 4;
    double lipschitz = -1;
    std::string max_error = kDefaultMaxError;
    bool quiet = false, repair = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("INPUT", a->input, kFieldInputHelp)->required();
  cmd->add_option("-o,--output", a->output,
                  "Output mesh (.stl binary, .obj, .ply binary, or .3mf for slicers), written atomically")
      ->required();
  add_units_option(cmd, a->units);
  auto* res = cmd->add_option("--resolution,-r", a->resolution, "Cells across the longest side of the bounds")
                  ->check(CLI::Validator(
                      [](std::string& s) -> std::string {
                        int v = 0;
                        if (!CLI::detail::lexical_cast(s, v) || v < 1 || v > kMaxMeshResolution)
                          return "the resolution must be a whole number from 1 to " +
                                 std::to_string(kMaxMeshResolution) + " (cells along an axis), got " + s;
                        return {};
                      },
                      "1.." + std::to_string(kMaxMeshResolution)));
  auto* cell = cmd->add_option("--cell", a->cell, "Cell edge length (cubic cells)")
                   ->check(CLI::Validator(
                       [](std::string& s) -> std::string {
                         double v = 0;
                         if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v) || !(v > 0))
                           return "the cell size must be a finite number > 0, got " + s;
                         return {};
                       },
                       "SIZE > 0"));
  res->excludes(cell);
  cell->excludes(res);
  cmd->add_option("--bounds", a->bounds,
                  "Region to mesh, x0,y0,z0,x1,y1,z1 (default: the box the input carries, a mesh's own or the one "
                  "frep convert wrote, else found by interval search of the expression; a shape reaching the bounds "
                  "is cut and closed there)")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--method", a->method, "dc: dual contouring (sharp features); snap: voxels snapped to the surface")
      ->check(CLI::IsMember({"dc", "snap"}))
      ->capture_default_str();
  cmd->add_option("--snap-gradient", a->gradient, "Gradient for --method snap: analytic or central (differences)")
      ->check(CLI::IsMember({"analytic", "central"}))
      ->capture_default_str();
  cmd->add_option("--snap-iterations", a->snap_iterations, "Newton steps per vertex for --method snap")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  cmd->add_option("--threads,-j", a->threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
  add_lipschitz_option(cmd, a->lipschitz);
  add_max_error_option(cmd, a->max_error);
  add_repair_option(cmd, a->repair);
  cmd->callback([a, res, cell] {
    if (res->count() == 0 && cell->count() == 0)
      throw CLI::ValidationError("--resolution/--cell", "give the cell size: --resolution N or --cell SIZE");
    MeshOptions o;
    if (!a->bounds.empty()) o.bounds = bounds_option(a->bounds);
    if (res->count()) o.resolution = a->resolution;
    if (cell->count()) o.cell_size = a->cell;
    o.method = a->method == "snap" ? MeshMethod::Snap : MeshMethod::DualContouring;
    o.snap.gradient = a->gradient == "central" ? SnapGradient::CentralDifferences : SnapGradient::Analytic;
    o.snap.iterations = a->snap_iterations;
    o.threads = a->threads;
    apply_max_error(a->max_error, o);
    check_output_path(a->output, a->input);

    const Model m = load_input(a->input, a->quiet, nullptr, a->repair);
    const Tape tape = Tape::compile(*m.graph, m.root);
    o.lipschitz = lipschitz_of(m, a->lipschitz);
    // A box known to hold the inside (a mesh's, converted here or by frep convert) instead of the
    // interval search, which is slow on big converted meshes.
    if (a->bounds.empty()) o.known_bounds = m.info.bounds;
    // Progress on long runs, on a terminal only (carriage returns would clutter a log).
    const auto t0 = std::chrono::steady_clock::now();
    const bool show = !a->quiet && ::isatty(STDERR_FILENO);
    bool shown = false;
    if (show)
      o.progress = [&](const MeshProgress& p) {
        if (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(1)) return;
        std::fprintf(stderr, "\rmeshing: %s %3.0f%%", p.phase, 100 * p.fraction);
        std::fflush(stderr);
        shown = true;
      };
    Mesher mesher(o);
    TriMesh mesh;
    try {
      mesh = mesher.mesh(tape);
    } catch (const InputError& e) {
      if (!e.file().empty()) throw;
      throw InputError(a->input, 0, e.detail());  // name the expression the problem is with
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (shown) std::fprintf(stderr, "\r%40s\r", "");
    const MeshStats& st = mesher.stats();
    warn_unresolved(st.unresolved);
    if (!a->quiet) {
      if (st.bounds_known)
        fmt::print("bounds: {} .. {} (known from the input: the mesh's bounding box)\n", fmt_point(st.found.lo),
                   fmt_point(st.found.hi));
      else if (st.bounds_found)
        fmt::print("bounds: {} .. {} (found by interval search of the expression in {} rounds)\n", fmt_point(st.found.lo),
                   fmt_point(st.found.hi), st.search_rounds);
      else
        fmt::print("bounds: {} .. {} (given)\n", fmt_point(o.bounds.lo), fmt_point(o.bounds.hi));
    }
    if (mesh.triangles.empty()) {
      if (st.cells[0] == 0)  // the bounds search found nothing
        throw InputError(a->input, 0, "the expression is not negative anywhere: nothing to mesh");
      throw InputError(a->input, 0,
                       std::string("no sample of the grid is inside the shape: nothing to mesh (the shape is empty in "
                                   "the bounds, or thinner than a cell: try ") +
                           (a->cell > 0 ? "a smaller --cell)" : "a finer --resolution)"));
    }
    write_mesh_output(a->output, mesh, a->units);
    if (!a->quiet) {
      fmt::print("grid: {} x {} x {} cells of {:.6g} over {} .. {}\n", st.cells[0], st.cells[1], st.cells[2],
                 st.cell_size, fmt_point(st.bounds.lo), fmt_point(st.bounds.hi));
      if (st.capped) fmt::print("note: the shape reaches the bounds; it is cut there and closed with flat caps\n");
      print_mesh_notes(st);
      fmt::print("mesh: {} triangles, {} vertices ({}) in {:.2f} s\n", mesh.triangles.size(), mesh.vertices.size(),
                 o.method == MeshMethod::Snap ? "snap" : "dual contouring", seconds);
      fmt::print("wrote {}\n", a->output);
    }
  });
}

}  // namespace frep::cli
