// PointCloudEvaluator: the points are sorted along a Morton curve and split in halves
// recursively; each group whose box is small simplifies its parent's tape (scalar interval
// evaluation: a few bytes per instruction, unlike the 16-box evaluator's), and groups of 64
// points are evaluated with SIMD batches. For sparse points a batch on the full tape is cheapest.
#include "frep/eval/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/util/thread_pool.hpp"
#include "util/morton.hpp"

namespace frep {
namespace {

constexpr std::size_t kLeafPoints = 64;  // groups this small are evaluated, not split

}  // namespace

struct PointCloudEvaluator::Worker {
  IntervalEvaluator intervals;
  BatchEvaluator batch;
  GradEvaluator grad;
  std::vector<Tape> tapes;  // per depth of the halving
};

PointCloudEvaluator::PointCloudEvaluator(PointCloudOptions options) : options_(options) {
  pool_ = std::make_unique<ThreadPool>(options_.threads);
  for (int i = 0; i < pool_->size(); ++i) workers_.push_back(std::make_unique<Worker>());
}

PointCloudEvaluator::~PointCloudEvaluator() = default;

void PointCloudEvaluator::eval(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out,
                               std::size_t n) {
  run(tape, xs, ys, zs, out, n, [](Worker& w, const Tape& t, const float* x, const float* y, const float* z, float* o,
                                   std::size_t m) { w.batch.eval(t, x, y, z, o, m); });
}

void PointCloudEvaluator::eval_grad(const Tape& tape, const float* xs, const float* ys, const float* zs, Grad* out,
                                    std::size_t n) {
  run(tape, xs, ys, zs, out, n, [](Worker& w, const Tape& t, const float* x, const float* y, const float* z, Grad* o,
                                   std::size_t m) { w.grad.eval(t, x, y, z, o, m); });
}

template <class Out, class Leaf>
void PointCloudEvaluator::run(const Tape& tape, const float* xs, const float* ys, const float* zs, Out* out,
                              std::size_t n, Leaf&& leaf) {
  FREP_ASSERT(!tape.code().empty(), "point cloud evaluation needs a tape with register code");
  if (n == 0) return;
  const float* c[3] = {xs, ys, zs};
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(c[k][i])) lo[k] = std::min(lo[k], double(c[k][i])), hi[k] = std::max(hi[k], double(c[k][i]));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int k = 0; k < 3; ++k) {
      const double extent = hi[k] - lo[k];
      double q = extent > 0 ? (double(c[k][i]) - lo[k]) / extent * kMortonCells : 0.0;
      if (!(q >= 0)) q = 0;  // NaN, or below: anywhere will do
      code |= morton_spread(static_cast<std::uint64_t>(std::min(q, kMortonCells))) << k;
    }
    keys[i] = {code, static_cast<std::uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<float> px(n), py(n), pz(n);
  std::vector<Out> res(n);
  for (std::size_t i = 0; i < n; ++i) px[i] = xs[keys[i].second], py[i] = ys[keys[i].second], pz[i] = zs[keys[i].second];

  // Depth first over halves of the Morton order: a group's bounding box simplifies its parent's
  // tape (SSA only: register code is built where points get evaluated) until the group is small
  // or the tape is; then SIMD batches. Groups whose box is a large part of the cloud's are passed
  // through unsimplified (sparse points: a pass over a big tape would cost more than it saves).
  const double cloud = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                 (hi[2] - lo[2]) * (hi[2] - lo[2]));
  auto descend = [&](auto&& self, Worker& w, const Tape& t, std::size_t b, std::size_t e, std::size_t depth) -> void {
    const bool small = e - b <= kLeafPoints || t.size() < options_.min_tape || t.choice_count() == 0;
    if (small && !t.code().empty()) {
      for (std::size_t c = b; c < e; c += kLeafPoints) leaf(w, t, &px[c], &py[c], &pz[c], &res[c], std::min(e, c + kLeafPoints) - c);
      return;
    }
    float l[3] = {px[b], py[b], pz[b]}, h[3] = {px[b], py[b], pz[b]};
    bool known = true;
    for (std::size_t i = b; i < e; ++i) {
      const float v[3] = {px[i], py[i], pz[i]};
      for (int k = 0; k < 3; ++k) {
        known &= std::isfinite(v[k]);
        l[k] = std::min(l[k], v[k]);
        h[k] = std::max(h[k], v[k]);
      }
    }
    const double diag = std::sqrt(double(h[0] - l[0]) * (h[0] - l[0]) + double(h[1] - l[1]) * (h[1] - l[1]) +
                                  double(h[2] - l[2]) * (h[2] - l[2]));
    const Tape* next = &t;
    // Simplify for a small box; and always before evaluating a tape that has no register code
    // (an unknown box, with a NaN coordinate, simplifies to the same instructions).
    if ((known && diag <= options_.max_box * cloud) || (small && t.code().empty())) {
      Tape& dst = w.tapes[depth];
      const Interval nan = Interval::unknown();
      if (known) w.intervals.eval(t, {l[0], h[0]}, {l[1], h[1]}, {l[2], h[2]});
      else w.intervals.eval(t, nan, nan, nan);
      t.simplify(w.intervals.values(), w.intervals.choices(), dst, /*registers=*/small);
      next = &dst;
    }
    if (small) {
      for (std::size_t c = b; c < e; c += kLeafPoints)
        leaf(w, *next, &px[c], &py[c], &pz[c], &res[c], std::min(e, c + kLeafPoints) - c);
      return;
    }
    const std::size_t mid = b + (e - b) / 2;
    self(self, w, *next, b, mid, depth + 1);
    self(self, w, *next, mid, e, depth + 1);
  };
  // Parallel over contiguous chunks; each worker keeps a tape per depth (depth <= log2 n).
  for (auto& w : workers_)
    if (w->tapes.size() < 64) w->tapes.resize(64);
  const std::size_t chunks = std::min<std::size_t>(static_cast<std::size_t>(4 * pool_->size()),
                                                   (n + kLeafPoints - 1) / kLeafPoints);
  pool_->parallel_for(static_cast<int>(chunks), [&](int wi, int ci) {
    Worker& w = *workers_[static_cast<std::size_t>(wi)];
    const std::size_t b = n * static_cast<std::size_t>(ci) / chunks, e = n * (static_cast<std::size_t>(ci) + 1) / chunks;
    if (b < e) descend(descend, w, tape, b, e, 0);
  });
  for (std::size_t i = 0; i < n; ++i) out[keys[i].second] = res[i];
}

void eval_points(const Tape& tape, const float* xs, const float* ys, const float* zs, float* out, std::size_t n,
                 const PointCloudOptions& options) {
  PointCloudEvaluator ev(options);
  ev.eval(tape, xs, ys, zs, out, n);
}

}  // namespace frep
