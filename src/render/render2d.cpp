#include "frep/render/render2d.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <thread>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/util/thread_pool.hpp"

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
  IntervalBatchEvaluator boxes;
  BatchEvaluator batch;
  std::vector<std::array<Tape, IntervalBatchEvaluator::kLanes>> tapes;  // per level, per child
  std::vector<float> xs, ys, zs, out;
};

Renderer2D::Renderer2D(RenderOptions options) : options_(std::move(options)) {
  check_options(options_);
  pool_ = std::make_unique<ThreadPool>(options_.threads);
  for (int i = 0; i < pool_->size(); ++i) workers_.push_back(std::make_unique<Worker>());
}

Renderer2D::~Renderer2D() = default;

namespace {
struct Rect {
  int x0, x1, y0, y1;  // pixels [x0, x1) x [y0, y1), rows from the top
};
struct Item {
  Rect rect;
  const Tape* tape;  // valid inside rect
};
}  // namespace

Image Renderer2D::render(const Tape& tape) {
  FREP_ASSERT(!tape.code().empty(), "render needs a tape with register code");
  const int n = options_.size;
  const std::vector<float> lin = linspace(n);
  Image img;
  img.width = img.height = n;
  img.pixels.assign(static_cast<std::size_t>(n) * n, 0);
  const std::vector<int>& tiles = options_.tiles;
  const int levels = static_cast<int>(tiles.size());
  const float z = options_.z;
  constexpr int kLanes = IntervalBatchEvaluator::kLanes;

  auto fill = [&](const Rect& r, std::uint8_t v) {
    for (int row = r.y0; row < r.y1; ++row)
      std::memset(&img.pixels[static_cast<std::size_t>(row) * n + r.x0], v, static_cast<std::size_t>(r.x1 - r.x0));
  };
  // Evaluates every pixel of an undecided tile of the last level.
  auto leaf = [&](Worker& w, const Tape& t, const Rect& rc) {
    const std::size_t width = static_cast<std::size_t>(rc.x1 - rc.x0);
    const std::size_t count = width * static_cast<std::size_t>(rc.y1 - rc.y0);
    if (w.xs.size() < count) {
      w.xs.resize(count);
      w.ys.resize(count);
      w.out.resize(count);
    }
    if (w.zs.size() < count || w.zs[0] != z) w.zs.assign(std::max(count, w.zs.size()), z);
    float* xs = w.xs.data();
    float* ys = w.ys.data();
    for (int row = rc.y0; row < rc.y1; ++row, xs += width, ys += width) {
      std::memcpy(xs, &lin[rc.x0], width * sizeof(float));
      std::fill(ys, ys + width, lin[n - 1 - row]);
    }
    w.batch.eval(t, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), count);
    const float* v = w.out.data();
    for (int row = rc.y0; row < rc.y1; ++row, v += width) {
      std::uint8_t* dst = &img.pixels[static_cast<std::size_t>(row) * n + rc.x0];
      for (std::size_t c = 0; c < width; ++c) dst[c] = v[c] < 0 ? 255 : 0;
    }
  };
  // Splits `parent` (valid tape `t`) into tiles of level `level`, 16 at a time: one SIMD
  // interval pass classifies them, one shared pass simplifies `t` for the undecided ones (into
  // outs(group)), and `next(child)` receives each undecided child.
  auto split = [&](Worker& w, const Tape& t, int level, const Rect& parent, auto&& outs, auto&& next) {
    const int step = tiles[level];
    const bool last = level + 1 == levels;
    Rect rects[kLanes];
    Interval xi[kLanes], yi[kLanes], zi[kLanes];
    int count = 0, group = 0;
    auto flush = [&] {
      w.boxes.eval(t, xi, yi, zi, count);
      std::uint32_t open = 0;
      for (int k = 0; k < count; ++k) {
        const Interval r = w.boxes.result(k);
        if (!r.is_unknown() && r.hi < 0) fill(rects[k], 255);
        else if (!r.is_unknown() && r.lo >= 0) fill(rects[k], 0);
        else open |= 1u << k;
      }
      if (open) {
        // Nothing to prune without choices, unless the children need register code.
        const bool reuse = t.choice_count() == 0 && (!last || !t.code().empty());
        Tape* dst = outs(group);
        if (!reuse) w.boxes.simplify(t, open, dst, last);
        for (std::uint32_t bits = open; bits; bits &= bits - 1) {
          const int k = __builtin_ctz(bits);
          next(Item{rects[k], reuse ? &t : &dst[k]});
        }
      }
      count = 0;
      ++group;
    };
    for (int ty = parent.y0; ty < parent.y1; ty += step)
      for (int tx = parent.x0; tx < parent.x1; tx += step) {
        const Rect rc{tx, std::min(tx + step, parent.x1), ty, std::min(ty + step, parent.y1)};
        rects[count] = rc;
        xi[count] = {lin[rc.x0], lin[rc.x1 - 1]};
        yi[count] = {lin[n - 1 - (rc.y1 - 1)], lin[n - 1 - rc.y0]};
        zi[count] = Interval::point(z);
        if (++count == kLanes) flush();
      }
    if (count) flush();
  };
  // Depth first below the parallel frontier; recursion depth is the number of levels.
  auto descend = [&](auto&& self, Worker& w, const Item& item, int level) -> void {
    if (level + 1 == levels) return leaf(w, *item.tape, item.rect);
    split(w, *item.tape, level + 1, item.rect, [&](int) { return w.tapes[level + 1].data(); },
          [&](const Item& child) { self(self, w, child, level + 1); });
  };

  // Breadth first for the first two levels, so that the parallel work items below are many and
  // small enough to balance. Simplified tapes of the frontier are kept per level. Every pixel is
  // written by exactly one item, so the image does not depend on the thread count.
  for (auto& w : workers_)
    if (static_cast<int>(w->tapes.size()) < levels) w->tapes.resize(levels);
  if (frontier_tapes_.size() < 2) frontier_tapes_.resize(2);
  std::vector<Item> frontier{{Rect{0, n, 0, n}, &tape}};
  int parent_step = n;
  const int bfs_levels = std::min(2, levels);
  for (int level = 0; level < bfs_levels; ++level) {
    const int per_edge = (parent_step + tiles[level] - 1) / tiles[level];
    const std::size_t groups = (static_cast<std::size_t>(per_edge) * per_edge + kLanes - 1) / kLanes;
    std::vector<Tape>& store = frontier_tapes_[level];
    if (store.size() < frontier.size() * groups * kLanes) store.resize(frontier.size() * groups * kLanes);
    std::vector<std::vector<Item>> parts(frontier.size());
    pool_->parallel_for(static_cast<int>(frontier.size()), [&](int wi, int i) {
      Worker& w = *workers_[wi];
      split(w, *frontier[i].tape, level, frontier[i].rect,
            [&](int g) { return &store[(static_cast<std::size_t>(i) * groups + g) * kLanes]; },
            [&](const Item& child) { parts[i].push_back(child); });
    });
    frontier.clear();
    for (auto& p : parts) frontier.insert(frontier.end(), p.begin(), p.end());
    parent_step = tiles[level];
  }
  pool_->parallel_for(static_cast<int>(frontier.size()),
                      [&](int wi, int i) { descend(descend, *workers_[wi], frontier[i], bfs_levels - 1); });
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
