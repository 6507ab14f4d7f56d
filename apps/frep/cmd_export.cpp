// `frep export`: write an expression as GLSL, a Shadertoy shader, C or LaTeX.
#include <fmt/core.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/export/c_source.hpp"
#include "frep/export/glsl.hpp"
#include "frep/export/latex.hpp"
#include "frep/script/load.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::cli {

void register_export(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "export", "Write an expression as GLSL (a function or a Shadertoy shader), C or LaTeX");
  cmd->footer(
      "Formats:\n"
      "  glsl       float sdf(vec3 p) with helper functions (GLSL 3.30 / ES 3.00), to paste into a shader\n"
      "  shadertoy  a complete Shadertoy Image shader that ray-marches the shape (drag to orbit)\n"
      "  c          float frep_sdf(float x, float y, float z), C99 + <math.h>, frep's f32 semantics\n"
      "  latex      a document (or --fragment) with the expression as mathematics\n"
      "Without --format, the extension of -o decides: .glsl/.frag, .c/.h, .tex.\n"
      "Meshes (and expressions holding them) are written as data plus a loop in C and GLSL; --closed-form\n"
      "writes their closed form instead (~75 nodes per triangle; LaTeX always does).\n"
      "Details: docs/export.md.");
  struct Args {
    std::string file, output, format, name;
    LatexOptions latex;
    ShadertoyOptions shadertoy;
    bool fragment = false, quiet = false, closed_form = false;
    int nan_checks = -1;  // -1: the format's default
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->file, kFieldInputHelp)->required();
  cmd->add_option("-o,--output", a->output, "Output file ('-' for standard output)")->required();
  cmd->add_option("--format,-f", a->format, "glsl, shadertoy, c or latex")
      ->check(CLI::IsMember({"glsl", "shadertoy", "c", "latex"}));
  cmd->add_option("--name", a->name, "Function name (glsl, shadertoy: sdf; c: frep_sdf)");
  cmd->add_flag("--fragment", a->fragment, "latex: only the align* environments (needs amsmath), no document");
  cmd->add_option("--digits", a->latex.digits,
                  "latex: significant digits of constants (0 = exact: the shortest text that reads back as the same f32)")
      ->capture_default_str()
      ->check(CLI::Range(0, 9));
  cmd->add_option("--line-width", a->latex.line_width, "latex: characters of mathematics per line before wrapping")
      ->capture_default_str()
      ->check(CLI::Range(20, 10000));
  cmd->add_option("--radius", a->shadertoy.radius, "shadertoy: the shape lies in [-R, R]^3")
      ->capture_default_str()
      ->check(finite_number(true));
  cmd->add_option("--step-scale", a->shadertoy.step_scale,
                  "shadertoy: sphere-tracing step as a fraction of the field value, below 1 for fields steeper "
                  "than a distance (0 = from the gradient sampled in the cube)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--max-steps", a->shadertoy.max_steps, "shadertoy: ray-marching steps per pixel")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_flag_callback("--nan-checks", [a] { a->nan_checks = 1; },
                         "glsl, shadertoy: min/max/compare propagate NaN as frep does (default for glsl)");
  cmd->add_flag_callback("--no-nan-checks", [a] { a->nan_checks = 0; },
                         "glsl, shadertoy: GLSL's min/max instead: frep's values except for NaN, and large "
                         "shaders compile about 3 times faster (default for shadertoy)");
  cmd->add_flag("--closed-form", a->closed_form,
                "glsl, shadertoy, c: meshes as their closed-form expression (~75 nodes per triangle) instead of "
                "triangle data plus a loop (latex: always)");
  cmd->add_flag("--quiet,-q", a->quiet, "Do not print what was written");
  cmd->callback([a] {
    std::string format = a->format;
    if (format.empty()) {
      const std::string ext = std::filesystem::path(a->output).extension().string();
      if (ext == ".glsl" || ext == ".frag") format = "glsl";
      else if (ext == ".c" || ext == ".h") format = "c";
      else if (ext == ".tex") format = "latex";
      else
        throw CLI::ValidationError("--format", "no --format given and the extension of '" + a->output +
                                                   "' does not say (.glsl or .frag, .c, .h, .tex)");
    }
    if (a->fragment && format != "latex") throw CLI::ValidationError("--fragment", "only applies to --format latex");
    if (a->nan_checks >= 0 && format != "glsl" && format != "shadertoy")
      throw CLI::ValidationError("--nan-checks", "only applies to --format glsl and shadertoy");
    const auto t0 = std::chrono::steady_clock::now();
    // Writes `m` in the chosen format; options are checked by the library.
    auto write = [&](std::ostream& out, const Model& m, const std::string& source) {
      if (format == "c") {
        CExportOptions opt;
        opt.source = source;
        opt.closed_form = a->closed_form;
        if (!a->name.empty()) opt.function_name = a->name;
        write_c(out, *m.graph, m.root, opt);
      } else if (format == "glsl") {
        GlslOptions opt;
        opt.source = source;
        opt.closed_form = a->closed_form;
        if (!a->name.empty()) opt.function_name = a->name;
        if (a->nan_checks >= 0) opt.nan_checks = a->nan_checks == 1;
        write_glsl(out, *m.graph, m.root, opt);
      } else if (format == "shadertoy") {
        ShadertoyOptions opt = a->shadertoy;
        opt.glsl.source = source;
        opt.glsl.closed_form = a->closed_form;
        if (!a->name.empty()) opt.glsl.function_name = a->name;
        if (a->nan_checks >= 0) opt.glsl.nan_checks = a->nan_checks == 1;
        write_shadertoy(out, *m.graph, m.root, opt);
      } else {
        LatexOptions opt = a->latex;
        opt.source = source;
        opt.standalone = !a->fragment;
        write_latex(out, *m.graph, m.root, opt);
      }
    };
    {
      // Option errors (a bad --name) are command-line errors: find them on a trivial expression
      // before reading the input.
      Model probe;
      probe.root = probe.graph->var_x();
      std::ostringstream sink;
      try {
        write(sink, probe, "");
      } catch (const InputError& e) {
        throw CLI::ValidationError(e.detail());
      }
    }
    if (a->output != "-") check_output(a->output, {a->file});
    const Model m = load_input(a->file, a->quiet);
    const std::string source = std::filesystem::path(a->file).filename().string();
    auto produce = [&](std::ostream& out) {
      try {
        write(out, m, source);
      } catch (const InputError& e) {
        // The exporters' own input errors (meshes too big for GLSL's constant arrays) concern
        // the input file.
        if (!e.file().empty()) throw;
        throw InputError(a->file, 0, e.detail());
      }
    };
    if (a->output == "-") {
      produce(std::cout);
      std::cout.flush();
      return;
    }
    write_file_atomically(a->output, produce);
    const auto t1 = std::chrono::steady_clock::now();
    if (!a->quiet)
      fmt::print("wrote {} ({}, {} nodes, {:.0f} ms)\n", a->output, format, reachable_nodes(*m.graph, m.root).size(),
                 std::chrono::duration<double, std::milli>(t1 - t0).count());
  });
}

}  // namespace frep::cli
