#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "commands.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/script/load.hpp"
#include "frep/io/points.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::cli {

void register_eval(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Evaluate an expression at points, one value per line (%.9g)");
  struct Args {
    std::string file, points;
    bool grad = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->file, kFieldInputHelp)->required();
  cmd->add_option("--points,-p", a->points,
                  "Points file, one 'x y z' per line (commas allowed; 'x y' means z = 0); - for stdin")
      ->required();
  cmd->add_flag("--grad,-g", a->grad, "Also print d/dx d/dy d/dz after each value");
  cmd->callback([a] {
    const Model m = load_input(a->file);
    // Coordinates beyond float32 would be infinite: refused, as by sdf.
    const PointColumns<float> p = parse_points_f32(read_points_text(a->points), points_source_name(a->points),
                                                   std::numeric_limits<float>::max());
    const Tape tape = Tape::compile(*m.graph, m.root);
    const std::size_t n = p.x.size();
    std::string out;
    char buf[160];
    // Scattered points with pruning: a converted mesh's expression has millions of nodes, of
    // which each point needs only the nearby ones (results equal the full tape's, bit for bit).
    PointCloudEvaluator ev;
    if (a->grad) {
      std::vector<Grad> g(n);
      ev.eval_grad(tape, p.x.data(), p.y.data(), p.z.data(), g.data(), n);
      for (const Grad& r : g) {
        std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g\n", r.v, r.dx, r.dy, r.dz);
        out += buf;
      }
    } else {
      std::vector<float> v(n);
      ev.eval(tape, p.x.data(), p.y.data(), p.z.data(), v.data(), n);
      for (float r : v) {
        std::snprintf(buf, sizeof buf, "%.9g\n", r);
        out += buf;
      }
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
  });
}

}  // namespace frep::cli
