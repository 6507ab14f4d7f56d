#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "frep/error.hpp"
#include "frep/io/load.hpp"
#include "frep/render/render2d.hpp"

namespace frep::cli {

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render", "Render a 2D expression (z = 0) over [-1,1]^2: white where the value is negative");
  struct Args {
    std::string file, output;
    RenderOptions opt;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->file, "Expression file (.vm)")->required();
  cmd->add_option("-o,--output", a->output, "Output image (.png or .pgm)")->required();
  cmd->add_option("--size,-s", a->opt.size, "Image width and height in pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--threads,-j", a->opt.threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--z", a->opt.z, "Slice height for 3D expressions")->capture_default_str();
  cmd->add_option("--tiles", a->opt.tiles,
                  "Tile edge per subdivision level, largest first (advanced; default 256,64,16)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", a->quiet, "Do not print where the image went");
  cmd->callback([a] {
    check_image_path(a->output);
    const Model m = load_expression(a->file);
    const Tape tape = Tape::compile(*m.graph, m.root);
    const auto t0 = std::chrono::steady_clock::now();
    const Image img = render2d(tape, a->opt);
    const auto t1 = std::chrono::steady_clock::now();
    save_image(a->output, img);
    if (!a->quiet)
      fmt::print("wrote {} ({}x{}, rendered in {:.1f} ms)\n", a->output, img.width, img.height,
                 std::chrono::duration<double, std::milli>(t1 - t0).count());
  });
}

}  // namespace frep::cli
