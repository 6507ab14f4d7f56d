// frep offset: a field (expression or converted mesh) grown or shrunk by a distance
// (ugf::offset, F - r), meshed or saved as an expression.
#include <fmt/core.h>

#include <cmath>

#include <optional>

#include "commands.hpp"
#include "field_output.hpp"
#include "input.hpp"
#include "frep/ugf/offset.hpp"

namespace frep::cli {

void register_offset(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "offset",
      "Grow (DIST > 0) or shrink (DIST < 0) a solid by a distance: F - DIST. Exact outside for a signed "
      "distance such as a converted mesh; corners grow round.");
  struct Args {
    std::string input, output;
    double distance = 0;
  };
  auto a = std::make_shared<Args>();
  auto o = std::make_shared<FieldOutputOptions>();
  cmd->add_option("INPUT", a->input, kFieldInputHelp)->required();
  cmd->add_option("DIST", a->distance, "Offset distance, in the input's units (> 0 grows, < 0 shrinks)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v)) return "the distance must be a finite number, got " + s;
            return {};
          },
          "NUMBER"));
  cmd->add_option("-o,--output", a->output, kFieldOutputHelp)->required();
  add_field_output_options(cmd, o);
  cmd->callback([a, o] {
    check_field_output_options(*o);
    check_field_output(a->output, a->input);
    Model m = load_input(a->input, o->quiet, nullptr, o->repair);
    note_if_not_a_distance("offset", a->input, m, o->quiet);
    o->lipschitz = lipschitz_of(m, o->lipschitz);  // an offset keeps it
    Field input = field_of(m);
    input.info.lipschitz = std::max(0.0, o->lipschitz);
    const Field result = ugf::offset(input, static_cast<float>(a->distance));
    const bool mesh_out = is_mesh_output(a->output);
    std::optional<Tape> tape;
    const FieldInfo info = output_facts(result, m, a->distance, mesh_out, tape);
    // Only a mesh output needs the region (an expression is saved whatever its bounds).
    const Box3 region = mesh_out ? input_region(a->input, info, *tape, *o) : Box3{};
    write_field_output(a->input, a->output, *m.graph, result.expr.id(), region, *o, info, tape ? &*tape : nullptr);
  });
}

}  // namespace frep::cli
