// frep render: the default black-and-white 2D picture (z = const), a shaded 3D view (--3d), or a
// signed-distance slice of an axis plane (--slice).
#include <fmt/core.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "commands.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/script/load.hpp"
#include "frep/render/render2d.hpp"
#include "frep/render/render3d.hpp"
#include "frep/render/shade.hpp"
#include "frep/render/slice.hpp"

namespace frep::cli {
namespace {

// "z=0.3" -> axis 2, offset 0.3.
bool parse_slice(const std::string& s, int& axis, float& offset) {
  if (s.size() < 3 || s[1] != '=') return false;
  const char a = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
  if (a < 'x' || a > 'z') return false;
  const char* begin = s.c_str() + 2;
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v) || std::fabs(v) > 3.4e38) return false;
  axis = a - 'x';
  offset = static_cast<float>(v);
  return true;
}

CLI::Validator slice_syntax() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        int axis = 0;
        float offset = 0;
        if (!parse_slice(s, axis, offset))
          return "expected AXIS=VALUE with AXIS one of x, y, z and VALUE a finite number (e.g. z=0.3), got '" + s + "'";
        return {};
      },
      "AXIS=VALUE");
}

CLI::Validator positive_finite() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v) || !(v > 0)) return "Value " + s + " is not a finite number > 0";
        return {};
      },
      "FINITE > 0");
}

}  // namespace

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render",
      "Render an expression: by default its sign on z = const over [-1,1]^2 (white where negative); "
      "--3d for a shaded view, --slice for a signed-distance slice");
  struct Args {
    std::string file, output, slice, view = "iso", mode = "shaded", up = "y";
    RenderOptions opt;
    std::vector<int> tiles;
    std::vector<double> rotate, bounds;
    double contour = 0, lipschitz = -1;
    int depth_steps = 0;
    bool three_d = false, ao = false, quiet = false, repair = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->file, kFieldInputHelp)->required();
  cmd->add_option("-o,--output", a->output, "Output image (.png; .pgm for grayscale pictures)")->required();
  cmd->add_option("--size,-s", a->opt.size, "Image width and height in pixels (3D and slices: the longer side)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--threads,-j", a->opt.threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  auto* z = cmd->add_option("--z", a->opt.z, "Slice height for 3D expressions (the default 2D picture)")
                ->check(finite_number())
                ->capture_default_str();
  cmd->add_option("--tiles", a->tiles,
                  "Tile edge per subdivision level, largest first (advanced; default 256,64,16; with --3d halving from the image size down to 4)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_flag("--quiet,-q", a->quiet, "Do not print where the image went");
  add_lipschitz_option(cmd, a->lipschitz);
  add_repair_option(cmd, a->repair);

  auto* three_d = cmd->add_flag("--3d", a->three_d, "Shaded 3D view of the surface f = 0 (orthographic)");
  auto* slice = cmd->add_option("--slice", a->slice,
                                "Signed-distance picture of an axis plane, AXIS=VALUE: z=0.3 shows (x, y), "
                                "y=.. shows (x, z), x=.. shows (y, z)")
                    ->check(slice_syntax());
  auto* view = cmd->add_option("--view", a->view,
                               "3D: the direction to look from (y up: front looks from +z; z up: front looks from -y)")
                   ->check(CLI::IsMember({"iso", "front", "back", "left", "right", "top", "bottom"}))
                   ->capture_default_str();
  auto* up = cmd->add_option("--up", a->up, "3D: the up axis, y (Fidget's models) or z (CAD and 3D printing)")
                 ->check(CLI::IsMember({"y", "z"}))
                 ->capture_default_str();
  auto* rotate = cmd->add_option("--rotate", a->rotate,
                                 "3D: yaw,pitch in degrees added to the view's (yaw turns about the up axis, pitch looks down)")
                     ->delimiter(',')
                     ->expected(2);
  auto* mode = cmd->add_option("--mode", a->mode,
                               "3D: shaded (lit), depth (grayscale height map, white = near) or normals (RGB normal map)")
                   ->check(CLI::IsMember({"shaded", "depth", "normals"}))
                   ->capture_default_str();
  auto* ao = cmd->add_flag("--ao", a->ao, "3D: ambient occlusion (darkens creases; from the depth map)");
  auto* depth = cmd->add_option("--depth-steps", a->depth_steps,
                                "3D: samples along each pixel's column (default 0: as many as pixels across the depth)")
                    ->check(CLI::Range(0, 65536));
  auto* bounds = cmd->add_option("--bounds", a->bounds,
                                 "3D and slices: the region shown, x0,y0,z0,x1,y1,z1 (default: the box the input carries, "
                                 "a mesh's bounding box, grown by 5% of its longest side, 20% for slices; else "
                                 "-1,-1,-1,1,1,1); 3D views cut the shape at its faces")
                     ->delimiter(',')
                     ->expected(6);
  auto* contour = cmd->add_option("--contour", a->contour,
                                  "Slices: contour spacing in units of the field (default: about a tenth of the picture, "
                                  "rounded to 1, 2 or 5 times a power of ten)")
                      ->check(positive_finite());
  three_d->excludes(slice)->excludes(z);
  slice->excludes(three_d)->excludes(z);
  for (CLI::Option* o : {view, up, rotate, mode, ao, depth}) o->needs(three_d);
  contour->needs(slice);

  cmd->callback([a, three_d, slice, bounds, contour] {
    Box3 box{{-1, -1, -1}, {1, 1, 1}};
    if (bounds->count()) {
      if (!three_d->count() && !slice->count())
        throw CLI::ValidationError("--bounds", "--bounds applies to --3d and --slice pictures only");
      box = bounds_option(a->bounds);
    }
    const bool grayscale = !three_d->count() && !slice->count() ? true : (three_d->count() && a->mode == "depth");
    for (std::size_t i = 1; i < a->tiles.size(); ++i)
      if (a->tiles[i] > a->tiles[i - 1]) throw CLI::ValidationError("--tiles", "tile sizes must not increase");
    check_image_path(a->output, grayscale ? 1 : 3);
    check_output(a->output, {a->file});
    const Model m = load_input(a->file, a->quiet, nullptr, a->repair);
    const Tape tape = Tape::compile(*m.graph, m.root);
    // Without --bounds, 3D views and slices show the box the input says holds its inside (a mesh,
    // converted here or by frep convert), grown by 5% of its longest side so that nothing is cut
    // (by 20% for slices, which show the field around the shape too).
    const bool framed = !bounds->count() && !m.info.bounds.empty();
    if (framed) {
      const Vec3 size = m.info.bounds.size();
      box = m.info.bounds.inflated((slice->count() ? 0.2 : 0.05) * std::max({size.x, size.y, size.z}));
      for (int i = 0; i < 3; ++i)
        if (!(box.lo[i] < box.hi[i])) box.lo[i] -= 1, box.hi[i] += 1;  // flat: give it some depth
    }
    const auto t0 = std::chrono::steady_clock::now();
    bool empty = false;  // a 3D view without a hit, a 2D picture without an inside pixel
    const auto draw = [&]() -> Image {
      if (three_d->count()) {
        Render3DOptions o;
        o.size = a->opt.size;
        o.threads = a->opt.threads;
        o.bounds = box;
        o.depth_steps = a->depth_steps;
        o.lipschitz = lipschitz_of(m, a->lipschitz);
        if (!a->tiles.empty()) o.tiles = a->tiles;
        parse_view_direction(a->view, o.view);
        o.z_up = a->up == "z";
        if (a->rotate.size() == 2) {
          o.yaw = a->rotate[0];
          o.pitch = a->rotate[1];
          if (!std::isfinite(o.yaw) || !std::isfinite(o.pitch))
            throw CLI::ValidationError("--rotate", "the angles must be finite numbers (degrees)");
        }
        ShadeOptions so;
        so.mode = a->mode == "depth" ? ShadeMode::Depth : a->mode == "normals" ? ShadeMode::Normals : ShadeMode::Shaded;
        so.ambient_occlusion = a->ao;
        so.threads = a->opt.threads;
        const DepthMap map = render3d(tape, o);
        empty = std::none_of(map.depth.begin(), map.depth.end(), [](float d) { return d == d; });
        return shade(map, so);
      }
      if (slice->count()) {
        SliceOptions o;
        parse_slice(a->slice, o.axis, o.offset);
        o.size = a->opt.size;
        o.threads = a->opt.threads;
        o.bounds = box;
        o.contour = contour->count() ? a->contour : 0;
        if (!a->tiles.empty()) o.tiles = a->tiles;
        return render_slice(tape, o);
      }
      RenderOptions o = a->opt;
      if (!a->tiles.empty()) o.tiles = a->tiles;
      o.lipschitz = lipschitz_of(m, a->lipschitz);
      Image im = render2d(tape, o);
      empty = std::all_of(im.pixels.begin(), im.pixels.end(), [](std::uint8_t v) { return v == 0; });
      return im;
    };
    Image img;
    try {
      img = draw();
    } catch (const InputError& e) {
      // Name the input the picture is of (and where its region came from).
      if (!e.file().empty()) throw;
      throw InputError(a->file, 0, e.detail() + (framed ? " (the region shown is the box the input carries)" : ""));
    }
    const auto t1 = std::chrono::steady_clock::now();
    save_image(a->output, img);
    // An empty picture is most often the wrong region: say which one was shown.
    if (empty && !a->quiet) {
      if (three_d->count())
        fmt::print(stderr, "frep render: warning: nothing of {} is in view (the region shown: {:.6g}, {:.6g}, {:.6g} .. {:.6g}, {:.6g}, {:.6g}{}); give --bounds\n",
                   a->file, box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z,
                   framed ? ", the box the input carries" : bounds->count() ? "" : ", the default");
      else
        fmt::print(stderr, "frep render: warning: {} is nowhere negative on z = {:.6g} over [-1,1]^2 (the 2D picture's "
                   "fixed region){}\n", a->file, a->opt.z,
                   m.info.bounds.empty() ? ": try --3d or --slice with --bounds"
                                         : ": try --3d or --slice, which show the box the input carries");
    }
    if (!a->quiet)
      fmt::print("wrote {} ({}x{}, rendered in {:.1f} ms)\n", a->output, img.width, img.height,
                 std::chrono::duration<double, std::milli>(t1 - t0).count());
  });
}

}  // namespace frep::cli
