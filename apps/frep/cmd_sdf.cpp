#include <cstdio>

#include "commands.hpp"
#include "input.hpp"
#include "frep/io/points.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"

namespace frep::cli {

void register_sdf(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sdf", "Exact signed distance to a mesh at points, one value per line (negative inside)");
  struct Args {
    std::string file, points, sign = "winding";
    bool unsigned_only = false, repair = false;
    double weld_tolerance = 0;
    int digits = 9;
    int threads = 0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("MESH", a->file, "Mesh file (STL, OBJ, PLY, OFF)")->required();
  cmd->add_option("--points,-p", a->points,
                  "Points file, one 'x y z' per line (commas allowed; 'x y' means z = 0); - for stdin")
      ->required();
  cmd->add_option("--sign", a->sign,
                  "Sign by the generalized 'winding' number (default; robust to holes and self-intersections) or "
                  "by the closest feature's 'pseudonormal' (exact on clean closed solids)")
      ->check(CLI::IsMember({"winding", "pseudonormal"}));
  cmd->add_flag("--unsigned", a->unsigned_only, "Print unsigned distances");
  add_repair_option(cmd, a->repair);
  cmd->add_option("--weld-tolerance", a->weld_tolerance, "Merge vertices closer than this (default 0: exact)")
      ->check(finite_non_negative());
  cmd->add_option("--digits", a->digits, "Significant digits printed (default 9, 17 round-trips doubles)")
      ->check(CLI::Range(1, 17));
  cmd->add_option("--threads", a->threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 1024));
  cmd->callback([a] {
    const PointColumns<double> p =
        parse_points_f64(read_points_text(a->points), points_source_name(a->points), kMaxQueryCoordinate);
    MeshDistanceOptions opt;
    opt.weld_tolerance = a->weld_tolerance;
    TriMesh mesh = repaired_if_asked(read_mesh_noting(a->file), a->repair, false);
    if (a->sign == "pseudonormal" && !a->unsigned_only) {
      // Pseudonormal signs are only meaningful on a closed, consistently oriented solid.
      ValidationOptions vo;
      vo.weld_tolerance = a->weld_tolerance;
      vo.threads = a->threads;
      const ValidationReport report = validate_mesh(mesh, vo);
      if (!report.is_solid())
        std::fprintf(stderr, "frep sdf: warning: %s: %s; pseudonormal signs may be wrong on it (--sign winding is robust)\n",
                     a->file.c_str(), report.summary().c_str());
    }
    const MeshDistance md(std::move(mesh), opt);
    const std::size_t n = p.size();
    std::vector<double> d(n);
    if (a->unsigned_only) {
      md.unsigned_distance(p.x.data(), p.y.data(), p.z.data(), d.data(), n, a->threads);
    } else {
      md.signed_distance(p.x.data(), p.y.data(), p.z.data(), d.data(), n,
                         a->sign == "pseudonormal" ? SignMethod::Pseudonormal : SignMethod::WindingNumber, a->threads);
    }
    std::string out;
    out.reserve(n * 16);
    char buf[64];
    for (double v : d) {
      std::snprintf(buf, sizeof buf, "%.*g\n", a->digits, v);
      out += buf;
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
  });
}

}  // namespace frep::cli
