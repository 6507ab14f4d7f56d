// The 2D renderer: a visitor of the subdivision driver that fills settled tiles and evaluates
// the pixels of the others.
#include "frep/render/render2d.hpp"

#include <algorithm>
#include <cstring>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"

namespace frep {
namespace {

// Pixel-center coordinates shared by every renderer, so tiled and brute-force images agree bit
// for bit: lin[i] = -1 + 2 i / (n - 1); row r has y = lin[n - 1 - r].
std::vector<float> linspace(int n) {
  std::vector<float> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[i] = n == 1 ? 0.0f : static_cast<float>(-1.0 + 2.0 * i / (n - 1));
  return v;
}

void check_options(const RenderOptions& o) {
  if (o.size < 1 || o.size > 16384)
    throw InputError("", 0, "image size must be between 1 and 16384, got " + std::to_string(o.size));
  if (o.tiles.empty()) throw InputError("", 0, "at least one tile level is needed");
  for (std::size_t i = 0; i < o.tiles.size(); ++i) {
    if (o.tiles[i] < 1) throw InputError("", 0, "tile sizes must be positive");
    if (i > 0 && o.tiles[i] > o.tiles[i - 1]) throw InputError("", 0, "tile sizes must decrease");
  }
}

}  // namespace

struct Renderer2D::Worker {
  BatchEvaluator batch;
  std::vector<float> xs, ys, zs, out;
};

Renderer2D::Renderer2D(RenderOptions options) : options_(std::move(options)) {
  check_options(options_);
  SubdivisionOptions so;
  so.tiles = options_.tiles;
  so.threads = options_.threads;
  so.lipschitz = options_.lipschitz;
  so.value_cap = 0.0f;  // pixels read only whether values are negative
  subdivider_ = std::make_unique<Subdivider>(so);
  for (int i = 0; i < subdivider_->workers(); ++i) workers_.push_back(std::make_unique<Worker>());
}

Renderer2D::~Renderer2D() = default;

Image Renderer2D::render(const Tape& tape) {
  FREP_ASSERT(!tape.code().empty(), "render needs a tape with register code");
  const int n = options_.size;
  const float z = options_.z;
  Image img;
  img.width = img.height = n;
  img.pixels.assign(static_cast<std::size_t>(n) * n, 0);
  // Grid index (column, row, 0); rows run from y = +1 at the top down to -1.
  SampleGrid grid;
  grid.coords[0] = linspace(n);
  grid.coords[1].assign(grid.coords[0].rbegin(), grid.coords[0].rend());
  grid.coords[2] = {z};
  const std::vector<float>& lin = grid.coords[0];
  const std::vector<float>& ys_of_row = grid.coords[1];

  struct Visitor {
    Renderer2D& r;
    Image& img;
    const std::vector<float>& lin;
    const std::vector<float>& ys_of_row;
    float z;

    void fill(const IndexBox& b, std::uint8_t v) {
      for (int row = b.lo[1]; row < b.hi[1]; ++row)
        std::memset(&img.pixels[static_cast<std::size_t>(row) * img.width + b.lo[0]], v,
                    static_cast<std::size_t>(b.extent(0)));
    }
    bool settled(int, const IndexBox& b, Interval v) {
      if (v.is_unknown()) return false;
      if (v.hi < 0) return fill(b, 255), true;
      if (v.lo >= 0) return fill(b, 0), true;
      return false;
    }
    // Evaluates every pixel of an undecided tile of the last level.
    void leaf(int wi, const Tape& t, const IndexBox& b) {
      Worker& w = *r.workers_[static_cast<std::size_t>(wi)];
      const std::size_t width = static_cast<std::size_t>(b.extent(0));
      const std::size_t count = width * static_cast<std::size_t>(b.extent(1));
      if (w.xs.size() < count) {
        w.xs.resize(count);
        w.ys.resize(count);
        w.out.resize(count);
      }
      if (w.zs.size() < count || w.zs[0] != z) w.zs.assign(std::max(count, w.zs.size()), z);
      float* xs = w.xs.data();
      float* ys = w.ys.data();
      for (int row = b.lo[1]; row < b.hi[1]; ++row, xs += width, ys += width) {
        std::memcpy(xs, &lin[static_cast<std::size_t>(b.lo[0])], width * sizeof(float));
        std::fill(ys, ys + width, ys_of_row[static_cast<std::size_t>(row)]);
      }
      w.batch.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), count);
      const float* v = w.out.data();
      for (int row = b.lo[1]; row < b.hi[1]; ++row, v += width) {
        std::uint8_t* dst = &img.pixels[static_cast<std::size_t>(row) * img.width + b.lo[0]];
        for (std::size_t c = 0; c < width; ++c) dst[c] = v[c] < 0 ? 255 : 0;
      }
    }
  } visitor{*this, img, lin, ys_of_row, z};
  // Every pixel belongs to exactly one box, so the image does not depend on the thread count.
  subdivider_->run(tape, grid, visitor);
  return img;
}

Image render2d(const Tape& tape, const RenderOptions& options) {
  Renderer2D r(options);
  return r.render(tape);
}

Image render2d_brute_force(const Tape& tape, const RenderOptions& options) {
  check_options(options);
  const int n = options.size;
  const std::vector<float> lin = linspace(n);
  Image img;
  img.width = img.height = n;
  img.pixels.assign(static_cast<std::size_t>(n) * n, 0);
  BatchEvaluator batch;
  std::vector<float> ys(static_cast<std::size_t>(n)), zs(static_cast<std::size_t>(n), options.z),
      out(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) {
    std::fill(ys.begin(), ys.end(), lin[n - 1 - r]);
    batch.eval(tape, lin.data(), ys.data(), zs.data(), out.data(), static_cast<std::size_t>(n));
    for (int c = 0; c < n; ++c) img.pixels[static_cast<std::size_t>(r) * n + c] = out[c] < 0 ? 255 : 0;
  }
  return img;
}

}  // namespace frep
