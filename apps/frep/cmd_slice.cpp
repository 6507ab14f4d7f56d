// frep slice: a field straight to G-code for 3D printing (or an SVG of its layers).
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/model/field.hpp"
#include "frep/model/transform.hpp"
#include "frep/render/image.hpp"
#include "frep/slice/gcode.hpp"
#include "frep/slice/layer_pictures.hpp"
#include "frep/slice/slicer.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::cli {
namespace {

enum class SliceOutput { Gcode, Svg };

SliceOutput output_kind(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".gcode" || ext == ".gco" || ext == ".g") return SliceOutput::Gcode;
  if (ext == ".svg") return SliceOutput::Svg;
  if (is_device(path)) return SliceOutput::Gcode;
  throw InputError(path, 0, "unknown output format: use a .gcode file name (or .svg for pictures of the layers)");
}

}  // namespace

void register_slice(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "slice",
      "Slice a part for 3D printing, straight from its field: G-code (walls at exact in-plane offsets of the exact "
      "cross-sections, skin, infill), or an SVG of the layers");
  struct Args {
    std::string input, output, config, pattern = "lines", preview;
    std::vector<std::string> set;
    std::vector<double> bounds;
    slice::PrintSettings s;
    int preview_layer = -1, preview_size = 1200, threads = 0;
    double lipschitz = -1, scale = 1;
    std::string svg_layers;
    bool quiet = false, repair = false, keep = false, list = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("INPUT", a->input, kFieldInputHelp);
  cmd->add_option("-o,--output", a->output,
                  "Output: .gcode (G-code), or .svg (every layer as a group; the --preview-layer one shown); written "
                  "atomically");
  auto* lh = cmd->add_option("--layer-height", a->s.layer_height, "Layer height in mm")->capture_default_str();
  auto* lw = cmd->add_option("--line-width", a->s.line_width, "Width of every extruded line in mm")->capture_default_str();
  auto* per = cmd->add_option("--perimeters", a->s.perimeters, "Walls around each island")->capture_default_str();
  auto* inf = cmd->add_option("--infill", a->s.infill, "Sparse infill density in percent")->capture_default_str();
  auto* pat = cmd->add_option("--infill-pattern", a->pattern, "lines, grid, or gyroid (evaluated from its field)")
                  ->check(CLI::IsMember({"lines", "grid", "gyroid"}))
                  ->capture_default_str();
  auto* top = cmd->add_option("--top-layers", a->s.top_layers, "Solid layers under top surfaces")->capture_default_str();
  auto* bot = cmd->add_option("--bottom-layers", a->s.bottom_layers, "Solid layers over bottom surfaces")->capture_default_str();
  cmd->add_option("--config", a->config,
                  "Settings file of 'key = value' lines (# comments); options given on the command line win. "
                  "--list-settings shows the keys and their defaults")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->set, "One setting, KEY=VALUE (repeatable; as in --config, after it)");
  auto* keep = cmd->add_flag("--keep-position", a->keep,
                             "Keep the model's x and y (it must lie on the bed) instead of centring it; z always starts at 0");
  cmd->add_option("--bounds", a->bounds,
                  "Region to slice, x0,y0,z0,x1,y1,z1 in the model's units (before --scale; default: the box the input carries, a mesh's own, else found "
                  "by interval search; a shape reaching the bounds is cut there: lattices, half-spaces)")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--scale", a->scale,
                  "Scale the model uniformly before slicing (model units to millimetres: 25.4 for inches, 1000 for metres)")
      ->check(finite_number(true))
      ->capture_default_str();
  cmd->add_option("--svg-layers", a->svg_layers, "An SVG output holds these layers only: N or FIRST-LAST (default: all)");
  cmd->add_option("--preview", a->preview, "Also write a PNG picture of one layer (--preview-layer)");
  cmd->add_option("--preview-layer", a->preview_layer,
                  "The layer shown in --preview and in an SVG output (0 = first; default: the middle one)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--preview-size", a->preview_size, "The longer side of the --preview picture in pixels")
      ->check(CLI::Range(16, 16384))
      ->capture_default_str();
  cmd->add_option("--threads,-j", a->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
  cmd->add_flag("--list-settings", a->list, "Print every setting (for --config and --set) with its default, and exit");
  cmd->add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
  add_lipschitz_option(cmd, a->lipschitz);
  add_repair_option(cmd, a->repair);
  cmd->callback([a, cmd, lh, lw, per, inf, pat, top, bot, keep] {
    if (a->list) {
      const slice::PrintSettings d;
      fmt::print("# frep slice settings (mm, mm/s, degrees C, percent), with their defaults\n");
      for (const std::string& name : slice::print_setting_names())
        fmt::print("{} = {}\n", name, slice::print_setting_text(d, name));
      return;
    }
    if (a->input.empty()) throw CLI::RequiredError("INPUT");
    if (a->output.empty()) throw CLI::RequiredError("--output");
    // Defaults, then the file, then --set, then the options given.
    slice::PrintSettings s;
    if (!a->config.empty()) slice::read_print_settings(a->config, s);
    for (const std::string& kv : a->set) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos) throw CLI::ValidationError("--set", "expected KEY=VALUE, got '" + kv + "'");
      try {
        slice::set_print_setting(s, kv.substr(0, eq), kv.substr(eq + 1));
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--set", e.what());
      }
    }
    const auto given = [](CLI::Option* o) { return o->count() > 0; };
    if (given(lh)) s.layer_height = a->s.layer_height;
    if (given(lw)) s.line_width = a->s.line_width;
    if (given(per)) s.perimeters = a->s.perimeters;
    if (given(inf)) s.infill = a->s.infill;
    if (given(pat))
      s.infill_pattern = a->pattern == "grid" ? slice::InfillPattern::Grid
                         : a->pattern == "gyroid" ? slice::InfillPattern::Gyroid
                                                  : slice::InfillPattern::Lines;
    if (given(top)) s.top_layers = a->s.top_layers;
    if (given(bot)) s.bottom_layers = a->s.bottom_layers;
    if (given(keep)) s.keep_position = a->keep;
    slice::check_print_settings(s);
    const SliceOutput kind = output_kind(a->output);
    check_output(a->output, {a->input});
    if (!a->preview.empty()) {
      check_image_path(a->preview, 3);
      check_output(a->preview, {a->input});
    }

    const auto t0 = std::chrono::steady_clock::now();
    Model m = load_input(a->input, a->quiet, nullptr, a->repair);
    // The region replaces what the input says: the field is sliced inside it only.
    if (!a->bounds.empty()) m.info.bounds = bounds_option(a->bounds);
    FieldInfo info = m.info;
    Expr root = m.root_expr();
    if (a->scale != 1) {
      const Field scaled = frep::scale(field_of(m), {a->scale, a->scale, a->scale});
      root = scaled.expr;
      info = scaled.info;
    }
    const Tape tape = Tape::compile(*m.graph, root.id());
    slice::SlicerOptions o;
    o.threads = a->threads;
    // The field sliced is f(p / scale): a bound given for the input's field is divided by the scale.
    o.lipschitz = a->lipschitz >= 0 ? a->lipschitz / a->scale : info.lipschitz;
    const bool show = !a->quiet && ::isatty(STDERR_FILENO);
    bool shown = false;
    if (show)
      o.progress = [&](const slice::SliceProgress& p) {
        if (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(1)) return;
        std::fprintf(stderr, "\rslicing: %s %3.0f%%", p.phase, 100 * p.fraction);
        std::fflush(stderr);
        shown = true;
      };
    slice::SlicedPart part;
    try {
      part = slice::slice_field(tape, info, s, o);
    } catch (const InputError& e) {
      if (!e.file().empty()) throw;
      throw InputError(a->input, 0, e.detail());
    }
    if (shown) std::fprintf(stderr, "\r%40s\r", "");
    const int layers = static_cast<int>(part.layers.size());
    const int shown_layer = a->preview_layer >= 0 ? a->preview_layer : layers / 2;
    if (shown_layer >= layers)
      throw CLI::ValidationError("--preview-layer", fmt::format("the part has {} layers (0 to {})", layers, layers - 1));
    slice::GcodeStats st;
    if (kind == SliceOutput::Gcode)
      write_file_atomically(a->output, [&](std::ostream& out) { st = slice::write_gcode(out, part, s, a->input); });
    else {
      int first = 0, last = layers - 1;
      if (!a->svg_layers.empty()) {
        const auto dash = a->svg_layers.find('-');
        const auto whole = [&](const std::string& t, int& v) {
          const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
          return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size();
        };
        const bool ok = dash == std::string::npos
                            ? whole(a->svg_layers, first) && (last = first, true)
                            : whole(a->svg_layers.substr(0, dash), first) && whole(a->svg_layers.substr(dash + 1), last);
        if (!ok) throw CLI::ValidationError("--svg-layers", "expected N or FIRST-LAST, got '" + a->svg_layers + "'");
        if (first < 0 || last < first || last >= layers)
          throw CLI::ValidationError("--svg-layers", fmt::format("the part has layers 0 to {}, got '{}'", layers - 1, a->svg_layers));
      }
      const int shown_in_svg = std::clamp(shown_layer, first, last);
      write_file_atomically(a->output, [&](std::ostream& out) { slice::write_layers_svg(out, part, s, shown_in_svg, first, last); });
    }
    if (!a->preview.empty()) save_image(a->preview, slice::layer_preview(part, s, shown_layer, a->preview_size));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a->quiet) {
      fmt::print("part: {:.2f} x {:.2f} x {:.2f} mm, at x {:.2f} .. {:.2f}, y {:.2f} .. {:.2f} on the {:g} x {:g} mm bed\n",
                 part.hi.x - part.lo.x, part.hi.y - part.lo.y, part.height, part.lo.x, part.hi.x, part.lo.y, part.hi.y,
                 s.bed_x, s.bed_y);
      fmt::print("layers: {} of {:g} mm; cross-sections hold {:.1f} mm^3\n", layers, s.layer_height, part.volume);
      if (kind == SliceOutput::Gcode) {
        const int minutes = static_cast<int>(st.seconds / 60);
        fmt::print("g-code: {} moves, {:.0f} mm of filament ({:.1f} cm^3), about {}h{:02d} at the set speeds\n", st.moves,
                   st.filament, st.extruded_volume / 1000, minutes / 60, minutes % 60);
      }
      fmt::print("sliced in {:.2f} s; wrote {}{}\n", seconds, a->output, a->preview.empty() ? "" : " and " + a->preview);
    }
  });
}

}  // namespace frep::cli
