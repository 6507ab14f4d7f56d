#include <cstdio>
#include <cstdlib>

#include "commands.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/convert/make_solid.hpp"
#include "input.hpp"

namespace frep::cli {

void register_repair(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "repair",
      "Make a mesh into the solid it means (where its surface winds around: overlapping shells are "
      "united, crossings cut exactly, flipped shells turned, holes filled) and write it; the output "
      "passes frep check. Exit 0 on success, 1 if it cannot be repaired");
  struct Args {
    std::string mesh, output;
    bool json = false, quiet = false, no_fill = false, ascii = false;
    double weld_tolerance = 0, weld_relative = 1e-7, time_limit = 600;
    int threads = 0, resolution = 256;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("MESH", a->mesh, "Mesh file (.stl, .obj, .ply, .off)")->required();
  cmd->add_option("-o,--output", a->output, "Output mesh (.stl, .obj, .ply, .3mf in mm), written only on success")->required();
  cmd->add_flag("--json", a->json, "Print the report as JSON");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress lines on stderr");
  cmd->add_flag("--no-fill", a->no_fill, "Refuse meshes with holes instead of filling them");
  cmd->add_flag("--ascii", a->ascii, "ASCII STL instead of binary");
  cmd->add_option("--weld-tolerance", a->weld_tolerance,
                  "Merge vertices closer than this first, closing cracks (default 0: --weld-relative decides)")
      ->check(finite_non_negative());
  cmd->add_option("--weld-relative", a->weld_relative,
                  "Without --weld-tolerance: merge vertices closer than this fraction of the bounding-box diagonal "
                  "(default 1e-7; 0: identical positions only)")
      ->check(finite_non_negative());
  cmd->add_option("--time-limit", a->time_limit, "Give up after this many seconds of cutting (default 600; 0: no limit)")
      ->check(finite_non_negative());
  cmd->add_option("-r,--resolution", a->resolution,
                  "Cells across the approximation made where no exact repair is found (the winding-number field, "
                  "remeshed; default 256; 0: refuse such meshes instead)")
      ->check(CLI::Range(0, 2048));
  cmd->add_option("--threads", a->threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 1024));
  cmd->callback([a] {
    check_output(a->output, {a->mesh});
    const TriMesh mesh = read_mesh_noting(a->mesh);
    RepairOptions opt;
    opt.weld_tolerance = a->weld_tolerance;
    opt.weld_relative = a->weld_relative;
    opt.fill_holes = !a->no_fill;
    opt.time_limit = a->time_limit;
    opt.threads = a->threads;
    opt.quiet = a->quiet || a->json;
    opt.remesh_resolution = a->resolution;
    // STL stores floats: the repair works on float coordinates, so that what is written is what was checked.
    const MeshFormat out_format = format_from_extension(a->output);  // STL and 3MF store floats
    opt.float_coordinates = out_format == MeshFormat::Stl || out_format == MeshFormat::ThreeMf || is_device(a->output);
    RepairResult r = make_solid(mesh, opt);
    MeshWriteOptions wo;
    wo.ascii = a->ascii;
    write_mesh(a->output, r.mesh, wo);
    const std::string out = a->json ? repair_report_json(r.report) : format_repair_report(r.report);
    std::fwrite(out.data(), 1, out.size(), stdout);
    if (!a->json) std::printf("wrote %s\n", a->output.c_str());
    std::fflush(stdout);
  });
}

}  // namespace frep::cli
