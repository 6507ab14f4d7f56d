// Slices: the subdivision driver over a grid one cell thick (no tile is settled, but every tile
// gets a simplified tape), values and gradients at pixel centers, then signed-distance colouring.
#include "frep/render/slice.hpp"

#include <algorithm>
#include <cmath>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/render/camera.hpp"

namespace frep {
namespace {

void check_options(const SliceOptions& o) {
  if (o.size < 1 || o.size > 16384)
    throw InputError("", 0, "image size must be between 1 and 16384, got " + std::to_string(o.size));
  if (o.axis < 0 || o.axis > 2) throw InputError("", 0, "the slice axis must be x, y or z");
  if (!std::isfinite(o.offset)) throw InputError("", 0, "the slice position must be a finite number");
  if (!(o.contour >= 0) || !std::isfinite(o.contour)) throw InputError("", 0, "the contour spacing must be a finite number >= 0");
  const int r = slice_right_axis(o.axis), u = slice_up_axis(o.axis);
  if (!(o.bounds.size()[r] > 0) || !(o.bounds.size()[u] > 0) || !std::isfinite(o.bounds.size()[r]) ||
      !std::isfinite(o.bounds.size()[u]))
    throw InputError("", 0, "the slice bounds must have positive, finite extent along both image axes");
  if (o.tiles.empty()) throw InputError("", 0, "at least one tile level is needed");
  for (std::size_t i = 0; i < o.tiles.size(); ++i) {
    if (o.tiles[i] < 1) throw InputError("", 0, "tile sizes must be positive");
    if (i > 0 && o.tiles[i] > o.tiles[i - 1]) throw InputError("", 0, "tile sizes must decrease");
  }
}

// Edges of `count` square pixels of size `pixel` centered on `center`, ascending.
std::vector<float> edges(double center, double pixel, int count) {
  std::vector<float> e(static_cast<std::size_t>(count) + 1);
  for (int i = 0; i <= count; ++i) e[static_cast<std::size_t>(i)] = static_cast<float>(center + pixel * (i - count / 2.0));
  return e;
}

}  // namespace

int slice_right_axis(int axis) { return axis == 0 ? 1 : 0; }
int slice_up_axis(int axis) { return axis == 2 ? 1 : 2; }

double default_contour_spacing(double extent) {
  if (!(extent > 0) || !std::isfinite(extent)) return 1;
  const double target = extent / 10;
  double p = std::pow(10.0, std::floor(std::log10(target)));
  double best = p;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p <= target * (1 + 1e-9)) best = m * p;
  return best;
}

struct SliceRenderer::Worker {
  GradEvaluator grad;
  std::vector<float> xs, ys, zs;
  std::vector<Grad> out;
};

SliceRenderer::SliceRenderer(SliceOptions options) : options_(std::move(options)) {
  check_options(options_);
  SubdivisionOptions so;
  so.tiles = options_.tiles;
  so.threads = options_.threads;
  subdivider_ = std::make_unique<Subdivider>(so);
  for (int i = 0; i < subdivider_->workers(); ++i) workers_.push_back(std::make_unique<Worker>());
}

SliceRenderer::~SliceRenderer() = default;

SliceField SliceRenderer::field(const Tape& tape) {
  FREP_ASSERT(!tape.code().empty(), "slices need a tape with register code");
  const SliceOptions& o = options_;
  const int ra = slice_right_axis(o.axis), ua = slice_up_axis(o.axis);
  SliceField f;
  f.axis = o.axis;
  const double er = o.bounds.size()[ra], eu = o.bounds.size()[ua];
  fit_pixels(er, eu, o.size, f.width, f.height);
  f.pixel = std::max(er, eu) / o.size;
  std::vector<float> right_edges = edges(o.bounds.center()[ra], f.pixel, f.width);
  std::vector<float> up_edges = edges(o.bounds.center()[ua], f.pixel, f.height);
  std::reverse(up_edges.begin(), up_edges.end());  // top row first
  f.right = Camera::centers(right_edges);
  f.up = Camera::centers(up_edges);
  const std::size_t pixels = static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height);
  f.value.assign(pixels, 0);
  f.slope.assign(pixels, 0);

  // Pixels are cells, so that no box is a single point along an image axis: interval
  // simplification folds what is constant over a box, which would drop in-plane derivatives.
  SampleGrid grid;
  grid.cells = true;
  grid.coords[o.axis] = {o.offset, o.offset};
  grid.coords[ra] = std::move(right_edges);
  grid.coords[ua] = std::move(up_edges);
  grid.check("slice");
  struct Visitor {
    SliceRenderer& r;
    SliceField& f;
    int ra, ua, axis;
    float offset;
    bool settled(int, const IndexBox&, Interval) { return false; }  // every pixel needs its value
    void leaf(int wi, const Tape& t, const IndexBox& b) {
      Worker& w = *r.workers_[static_cast<std::size_t>(wi)];
      const std::size_t n = static_cast<std::size_t>(b.extent(ra)) * static_cast<std::size_t>(b.extent(ua));
      if (w.xs.size() < n) {
        w.xs.resize(n);
        w.ys.resize(n);
        w.zs.resize(n);
        w.out.resize(n);
      }
      float* coord[3] = {w.xs.data(), w.ys.data(), w.zs.data()};
      std::size_t i = 0;
      for (int row = b.lo[ua]; row < b.hi[ua]; ++row)
        for (int col = b.lo[ra]; col < b.hi[ra]; ++col, ++i) {
          coord[ra][i] = f.right[static_cast<std::size_t>(col)];
          coord[ua][i] = f.up[static_cast<std::size_t>(row)];
          coord[axis][i] = offset;
        }
      w.grad.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), n);
      i = 0;
      for (int row = b.lo[ua]; row < b.hi[ua]; ++row)
        for (int col = b.lo[ra]; col < b.hi[ra]; ++col, ++i) {
          const Grad& g = w.out[i];
          const float d[3] = {g.dx, g.dy, g.dz};
          const std::size_t p = static_cast<std::size_t>(row) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(col);
          f.value[p] = g.v;
          f.slope[p] = std::hypot(d[ra], d[ua]);
        }
    }
  } visitor{*this, f, ra, ua, o.axis, o.offset};
  subdivider_->run(tape, grid, visitor);
  return f;
}

Image SliceRenderer::render(const Tape& tape) {
  const SliceField f = field(tape);
  const double extent = std::max(f.width, f.height) * f.pixel;
  return colour_slice(f, options_.contour > 0 ? options_.contour : default_contour_spacing(extent));
}

Image render_slice(const Tape& tape, const SliceOptions& options) {
  SliceRenderer r(options);
  return r.render(tape);
}

Image colour_slice(const SliceField& f, double contour) {
  FREP_ASSERT(contour > 0, "contour spacing must be positive");
  using C = SliceColours;
  Image img;
  img.width = f.width;
  img.height = f.height;
  img.channels = 3;
  img.pixels.assign(static_cast<std::size_t>(f.width) * f.height * 3, 0);
  const double extent = std::max(f.width, f.height) * f.pixel;
  const int W = f.width, H = f.height;
  auto value = [&](int x, int y) { return static_cast<double>(f.value[static_cast<std::size_t>(y) * W + x]); };
  // Lines are drawn only where the field really crosses them within reach (a neighbour on the
  // other side), so that spikes of |grad f| do not draw lines from the distance estimate alone.
  auto crosses = [&](int x, int y, int reach, auto&& side) {
    const double v = value(x, y);
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
        const double q = value(qx, qy);
        if (q == q && side(q) != side(v)) return true;
      }
    return false;
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * W + x;
      std::uint8_t* px = &img.pixels[p * 3];
      const double v = f.value[p];
      if (v != v) {
        std::copy(C::nan, C::nan + 3, px);
        continue;
      }
      // Pixels per unit of f: the gradient turns value differences into distances. Without a
      // usable gradient, read f as a distance.
      double slope = f.slope[p];
      if (!(slope > 0) || !std::isfinite(slope)) slope = 1;
      const double per_unit = 1 / (slope * f.pixel);
      const std::uint8_t* base = v < 0 ? C::inside : C::outside;
      // Lines closer than 5 pixels fade out, and with them the banding.
      const double spacing = contour * per_unit;
      const double fade = std::clamp((spacing - 2) / 3, 0.0, 1.0);
      // Darker away from the surface, from 1 at f = 0 down to 0.5: flat between contour lines
      // (a contour map), smooth where the lines fade.
      const double a = std::fabs(v);
      const double banded = std::floor(a / contour) * contour;
      const double level = std::isfinite(a) ? fade * banded + (1 - fade) * a : a;
      const double shade = std::isfinite(level) ? 0.5 + 0.5 * std::exp(-3 * level / extent) : 0.5;
      double rgb[3];
      for (int c = 0; c < 3; ++c) rgb[c] = base[c] * shade;
      if (std::isfinite(v)) {
        // Contours every `contour`: thin lines.
        const double k = v / contour;
        const double off = std::fabs(k - std::round(k)) * contour * per_unit;  // pixels to the nearest contour
        const double cover = std::clamp(C::line_half_width + 0.5 - off, 0.0, 1.0) * fade;
        if (cover > 0 && crosses(x, y, 1, [&](double q) { return std::floor(q / contour); }))
          for (double& c : rgb) c *= 1 - cover * (1 - C::line_darkening);
        // The zero contour, bold, over everything.
        const double zoff = a * per_unit;
        const double zcover = std::clamp(C::zero_half_width + 0.5 - zoff, 0.0, 1.0);
        if (zcover > 0 && crosses(x, y, 2, [](double q) { return q < 0; }))
          for (int c = 0; c < 3; ++c) rgb[c] = rgb[c] * (1 - zcover) + C::zero[c] * zcover;
      }
      for (int c = 0; c < 3; ++c) px[c] = static_cast<std::uint8_t>(std::lround(std::clamp(rgb[c], 0.0, 255.0)));
    }
  return img;
}

}  // namespace frep
