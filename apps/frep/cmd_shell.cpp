// frep shell: a solid hollowed into a wall of constant thickness (for printing: inward by
// default), from an expression or a converted mesh; meshed or saved as an expression.
#include <fmt/core.h>

#include <cmath>

#include <optional>

#include "commands.hpp"
#include "field_output.hpp"
#include "input.hpp"
#include "frep/ugf/offset.hpp"

namespace frep::cli {

void register_shell(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "shell",
      "Hollow a solid into a wall of thickness T: inside the surface (default, the outer shape is kept), outside "
      "it, or centred on it. Exact where offsets of the input are (a converted mesh: outside; inside away from "
      "its medial axis).");
  struct Args {
    std::string input, output, side = "inward";
    double thickness = 0;
  };
  auto a = std::make_shared<Args>();
  auto o = std::make_shared<FieldOutputOptions>();
  cmd->add_option("INPUT", a->input, kFieldInputHelp)->required();
  cmd->add_option("THICKNESS", a->thickness, "Wall thickness, in the input's units (> 0)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v) || !(v > 0))
              return "the thickness must be a finite number > 0, got " + s;
            return {};
          },
          "T > 0"));
  cmd->add_option("-o,--output", a->output, kFieldOutputHelp)->required();
  cmd->add_option("--side", a->side,
                  "Where the wall goes: inward (max(F, -F - T), hollowing), outward (max(-F, F - T)) or centred "
                  "(|F| - T/2)")
      ->check(CLI::IsMember({"inward", "outward", "centred", "centered"}))
      ->capture_default_str();
  add_field_output_options(cmd, o);
  cmd->callback([cmd, a, o] {
    check_field_output_options(*o);
    check_field_output(a->output, a->input);
    Model m = load_input(a->input, o->quiet, nullptr, o->repair);
    note_if_not_a_distance("shell", a->input, m, o->quiet);
    o->lipschitz = lipschitz_of(m, o->lipschitz);  // every side keeps it (max and abs of L-Lipschitz fields)
    const float t = static_cast<float>(a->thickness);
    Field f = field_of(m);
    f.info.lipschitz = std::max(0.0, o->lipschitz);
    const bool outward = a->side == "outward", inward = a->side == "inward";
    const Field result = inward ? ugf::shell_inward(f, t) : outward ? ugf::shell_outward(f, t) : ugf::shell(f, t);
    const bool mesh_out = is_mesh_output(a->output);
    std::optional<Tape> tape;
    // The wall reaches beyond the input's surface by what it adds outside.
    const FieldInfo info = output_facts(result, m, inward ? 0.0 : outward ? a->thickness : a->thickness / 2, mesh_out, tape);
    if (mesh_out) {
      const Box3 region = input_region(a->input, info, *tape, *o);
      const Vec3 size = region.size();
      const double longest = std::max({size.x, size.y, size.z});
      // Without --resolution, the wall gets at least 3 cells across (up to 1024 cells), since
      // the default 128 loses most of a thin wall on a big part.
      if (cmd->get_option("--resolution")->count() == 0) {
        const double wanted = std::ceil(3 * longest / a->thickness);
        if (wanted > o->resolution) {
          const int r = static_cast<int>(std::min(wanted, 1024.0));
          if (!o->quiet)
            fmt::print(stderr, "frep shell: --resolution {} (instead of {}) so that the wall is {} cells thick\n", r,
                       o->resolution, r == 1024 ? "as many" : "3");
          o->resolution = r;
        }
      }
      const double cell = longest / o->resolution;
      if (!o->quiet && a->thickness < 2 * cell)
        fmt::print(stderr,
                   "frep: warning: the wall ({:.6g}) is thinner than two cells ({:.6g}); parts of it may be lost in the "
                   "mesh: raise --resolution\n",
                   a->thickness, cell);
      write_field_output(a->input, a->output, *m.graph, result.expr.id(), region, *o, info, &*tape);
    } else {
      write_field_output(a->input, a->output, *m.graph, result.expr.id(), Box3{}, *o, info);
    }
  });
}

}  // namespace frep::cli
