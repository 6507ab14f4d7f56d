#include <fmt/core.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "input.hpp"
#include "frep/convert/convert.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/script/save.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace frep::cli {

void register_convert(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "convert",
      "Convert a closed mesh (STL, OBJ, PLY, OFF) into an expression that is its exact signed distance "
      "(negative inside), written as .vm (Fidget's text format), .rhai (a Fidget script) or .frep (frep's "
      "compact binary format)");
  struct Args {
    std::string mesh, output, sign = "pseudonormal", tetgen = "tetgen";
    double weld_tolerance = 0, tetgen_timeout = 600;
    int threads = 0;
    bool quiet = false, repair = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("MESH", a->mesh, "Mesh file")->required();
  cmd->add_option("-o,--output", a->output, "Output expression (.vm, .rhai or .frep)")->required();
  cmd->add_option("--sign", a->sign,
                  "How inside is told from outside: 'pseudonormal' (default: the nearest feature's angle-weighted "
                  "normal; no external program) or 'tets' (the union of TetGen's tetrahedra; needs the tetgen program)")
      ->check(CLI::IsMember({"pseudonormal", "tets"}));
  cmd->add_option("--weld-tolerance", a->weld_tolerance,
                  "Merge vertices closer than this first, as `frep check --weld-tolerance` (default 0: identical "
                  "positions only)")
      ->check(finite_non_negative());
  cmd->add_option("--threads", a->threads, "Worker threads for the mesh check (default 0: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--tetgen", a->tetgen, "The TetGen program for --sign tets (default: tetgen on PATH)");
  cmd->add_option("--tetgen-timeout", a->tetgen_timeout, "Seconds TetGen may run (default 600)")
      ->check(CLI::Range(0.001, 1e7));
  cmd->add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
  add_repair_option(cmd, a->repair);
  cmd->callback([a] {
    check_expression_path(a->output);
    check_output(a->output, {a->mesh});
    const TriMesh mesh = repaired_if_asked(read_mesh_noting(a->mesh), a->repair, a->quiet);
    ConvertOptions opt;
    opt.sign = a->sign == "tets" ? SignMode::Tetrahedra : SignMode::Pseudonormal;
    opt.weld_tolerance = a->weld_tolerance;
    opt.threads = a->threads;
    opt.tetgen = a->tetgen;
    opt.tetgen_timeout = a->tetgen_timeout;
    const bool show_progress = !a->quiet && mesh.num_triangles() >= 20000;
    if (show_progress)
      opt.progress = [](const char* stage, double fraction) {
        std::fprintf(stderr, "frep convert: %3.0f%% %s\n", 100 * fraction, stage);
      };
    const ConvertResult r = convert_mesh(mesh, opt);
    const auto t0 = std::chrono::steady_clock::now();
    if (std::filesystem::path(a->output).extension() == ".frep" || is_device(a->output)) {
      // frep's own format keeps the triangles beside the closed form: reading it back evaluates
      // through the mesh (a mesh leaf), and writes the same formula again.
      auto closed = std::make_shared<const std::string>(serialize_frep(*r.model.graph, r.model.root, r.model.info));
      save_expression(a->output, mesh_model(std::make_shared<const MeshOracle>(mesh, opt, std::move(closed))),
                      &mesh_oracle_codec());
    } else {
      save_expression(a->output, r.model);
    }
    const double write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (a->quiet) return;
    const ConvertStats& s = r.stats;
    fmt::print("{}: {} triangles, {} vertices\n", a->mesh, s.triangles, s.vertices);
    fmt::print("  terms: {} flat regions ({} convex polygons), {} crease edges, {} vertices\n", s.flat_regions,
               s.polygons, s.edge_terms, s.vertex_terms);
    if (opt.sign == SignMode::Tetrahedra) fmt::print("  tetrahedra: {}\n", s.tetrahedra);
    fmt::print("  nodes: {} ({:.1f} per triangle), sign: {}\n", s.nodes,
               s.triangles ? static_cast<double>(s.nodes) / static_cast<double>(s.triangles) : 0.0, a->sign);
    fmt::print("  time: {:.2f} s to convert, {:.2f} s to write\n", s.seconds, write_s);
    fmt::print("wrote {}\n", a->output);
  });
}

}  // namespace frep::cli
