#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "commands.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/mesh/coordinate_range.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"

namespace frep::cli {

void register_check(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "check", "Validate a mesh (STL, OBJ, PLY, OFF): exit 0 only for a closed, manifold, consistently "
               "oriented solid without self-intersections; 4 otherwise");
  struct Args {
    std::string file;
    bool json = false, no_intersections = false;
    double weld_tolerance = 0;
    std::size_t examples = 5;
    int threads = 0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("MESH", a->file, "Mesh file")->required();
  cmd->add_flag("--json", a->json, "Print the report as JSON");
  cmd->add_option("--weld-tolerance", a->weld_tolerance,
                  "Merge vertices closer than this before checking (default 0: identical positions only)")
      ->check(finite_non_negative());
  cmd->add_option("--examples", a->examples, "Example locations listed per defect (default 5)")
      ->check(whole_non_negative());  // unsigned: "-1" would wrap to 2^64 - 1
  cmd->add_flag("--no-self-intersections", a->no_intersections, "Skip the self-intersection test");
  cmd->add_option("--threads", a->threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 1024));
  cmd->callback([a] {
    const TriMesh mesh = read_mesh_noting(a->file);
    ValidationOptions opt;
    opt.weld_tolerance = a->weld_tolerance;
    opt.self_intersections = !a->no_intersections;
    opt.max_examples = a->examples;
    opt.threads = a->threads;
    const ValidationReport report = validate_mesh(mesh, opt);
    const std::string out = a->json ? report.to_json() : report.to_text();
    std::fwrite(out.data(), 1, out.size(), stdout);
    std::fflush(stdout);
    // A solid whose coordinates float arithmetic cannot carry is no usable solid either.
    std::string beyond;
    if (report.is_solid()) {
      try {
        check_coordinate_range(mesh);
      } catch (const InputError& e) {
        beyond = e.detail();
      }
    }
    if (!beyond.empty()) {
      std::fprintf(stderr, "frep: %s: a valid solid, but not usable: %s\n", a->file.c_str(), beyond.c_str());
      std::exit(4);
    }
    if (!report.is_solid()) {
      if (a->json) std::fprintf(stderr, "frep: %s: %s\n", a->file.c_str(), report.summary().c_str());
      std::exit(4);
    }
  });
}

}  // namespace frep::cli
