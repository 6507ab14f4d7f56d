#include "frep/render/render2d.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"

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
  if (o.size < 1 || o.size > 65536)
    throw InputError("", 0, "image size must be between 1 and 65536, got " + std::to_string(o.size));
  if (o.tiles.empty()) throw InputError("", 0, "at least one tile level is needed");
  for (std::size_t i = 0; i < o.tiles.size(); ++i) {
    if (o.tiles[i] < 1) throw InputError("", 0, "tile sizes must be positive");
    if (i > 0 && o.tiles[i] > o.tiles[i - 1]) throw InputError("", 0, "tile sizes must decrease");
  }
}

}  // namespace

struct Renderer2D::Worker {
  IntervalEvaluator interval;
  BatchEvaluator batch;
  std::vector<Tape> tapes;  // one per level
  std::vector<float> xs, ys, zs, out;
};

Renderer2D::Renderer2D(RenderOptions options) : options_(std::move(options)) {
  check_options(options_);
  int n = options_.threads;
  if (n <= 0) n = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 0; i < n; ++i) workers_.push_back(std::make_unique<Worker>());
}

Renderer2D::~Renderer2D() = default;

Image Renderer2D::render(const Tape& tape) {
  const int n = options_.size;
  const std::vector<float> lin = linspace(n);
  Image img;
  img.width = img.height = n;
  img.pixels.assign(static_cast<std::size_t>(n) * n, 0);
  const std::vector<int>& tiles = options_.tiles;
  const float z = options_.z;
  const Interval zi = Interval::point(z);

  // Pixel rectangle [x0, x1) x [y0, y1) (rows from the top), evaluated with `t`, at `level`.
  auto fill = [&](int x0, int x1, int y0, int y1, std::uint8_t v) {
    for (int r = y0; r < y1; ++r) std::memset(&img.pixels[static_cast<std::size_t>(r) * n + x0], v, x1 - x0);
  };
  auto leaf = [&](Worker& w, const Tape& t, int x0, int x1, int y0, int y1) {
    const std::size_t count = static_cast<std::size_t>(x1 - x0) * (y1 - y0);
    w.xs.resize(count);
    w.ys.resize(count);
    w.zs.assign(count, z);
    w.out.resize(count);
    std::size_t k = 0;
    for (int r = y0; r < y1; ++r)
      for (int c = x0; c < x1; ++c, ++k) {
        w.xs[k] = lin[c];
        w.ys[k] = lin[n - 1 - r];
      }
    w.batch.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), count);
    k = 0;
    for (int r = y0; r < y1; ++r)
      for (int c = x0; c < x1; ++c, ++k) img.pixels[static_cast<std::size_t>(r) * n + c] = w.out[k] < 0 ? 255 : 0;
  };
  // Recursive over levels (depth = number of levels, a handful), not over the expression.
  auto tile = [&](auto&& self, Worker& w, const Tape& t, std::size_t level, int x0, int x1, int y0,
                  int y1) -> void {
    const Interval xi{lin[x0], lin[x1 - 1]};
    const Interval yi{lin[n - 1 - (y1 - 1)], lin[n - 1 - y0]};
    const Interval r = w.interval.eval(t, xi, yi, zi);
    if (!r.is_unknown()) {
      if (r.hi < 0) return fill(x0, x1, y0, y1, 255);
      if (r.lo >= 0) return fill(x0, x1, y0, y1, 0);
    }
    const Tape* next = &t;
    if (t.choice_count() > 0) {
      t.simplify(w.interval.values(), w.interval.choices(), w.tapes[level]);
      next = &w.tapes[level];
    }
    if (level + 1 >= tiles.size()) return leaf(w, *next, x0, x1, y0, y1);
    const int step = tiles[level + 1];
    for (int ty = y0; ty < y1; ty += step)
      for (int tx = x0; tx < x1; tx += step)
        self(self, w, *next, level + 1, tx, std::min(tx + step, x1), ty, std::min(ty + step, y1));
  };

  // Work items are the tiles of the first level, handed out dynamically; each pixel is written
  // by exactly one item, so the image does not depend on the thread count.
  const int step = tiles[0];
  const int per_row = (n + step - 1) / step;
  const int items = per_row * per_row;
  std::atomic<int> next_item{0};
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  auto run = [&](Worker& w) {
    try {
      if (w.tapes.size() < tiles.size()) w.tapes.resize(tiles.size());  // never while in use
      for (int i; (i = next_item.fetch_add(1)) < items && !failed.load();) {
        const int tx = (i % per_row) * step, ty = (i / per_row) * step;
        tile(tile, w, tape, 0, tx, std::min(tx + step, n), ty, std::min(ty + step, n));
      }
    } catch (...) {
      if (!failed.exchange(true)) error = std::current_exception();
    }
  };
  const std::size_t nthreads = std::min<std::size_t>(workers_.size(), static_cast<std::size_t>(items));
  std::vector<std::thread> pool;
  for (std::size_t i = 1; i < nthreads; ++i) pool.emplace_back(run, std::ref(*workers_[i]));
  run(*workers_[0]);
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
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
