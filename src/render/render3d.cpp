// The 3D renderer: a visitor of the subdivision driver that searches pixel columns front to
// back, and the brute-force reference that searches every column on the full tape.
//
// Per pixel, the result is defined by the samples alone: the first depth sample s with f < 0,
// then bisection between samples s - 1 and s (or the front of the volume if s = 0). The pruned
// search reaches exactly that:
// - A column's samples s - 1 and s lie in one box (the grid has cells along every axis, so a box
//   covers its samples lo..hi inclusive and the space between them). That box is not settled
//   (f(s - 1) is not < 0, f(s) is) and is not skipped (skipping needs an inside sample at or
//   before its lo <= s - 1), so its leaf finds the hit and refines it on a tape valid there.
// - Leaves and filled boxes lower `best`, the first inside sample known per pixel; boxes whose
//   pixels all have best <= lo cannot contain a nearer hit and are skipped. Leaves do not search
//   their first sample (unless it is the front): the box in front holds the segment ending there.
// - Results are written under a lock per image row, keyed by 2 s (refined) so the nearest wins;
//   a key is produced by exactly one box, so the image is the same for any thread count.
#include "frep/render/render3d.hpp"

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <mutex>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/expr/oracle.hpp"
#include "view_tape.hpp"

namespace frep {
namespace {

// Halving from the largest power of two below the volume's longest side (in voxels) down to 4:
// 8 children per split, so that large boxes (which prune little, and in rotated views least)
// are evaluated as few at a time as possible on the big tapes.
std::vector<int> automatic_tiles(const Camera& cam) {
  const int longest = std::max({cam.width, cam.height, cam.depth});
  int top = 4;
  while (top * 2 < longest) top *= 2;
  std::vector<int> tiles;
  for (int t = top; t >= 4; t /= 2) tiles.push_back(t);
  return tiles;
}

void check_options(const Render3DOptions& o) {
  if (o.size < 1 || o.size > 16384)
    throw InputError("", 0, "image size must be between 1 and 16384, got " + std::to_string(o.size));
  if (o.refine_steps < 0 || o.refine_steps > 64)
    throw InputError("", 0, "refine steps must be between 0 and 64, got " + std::to_string(o.refine_steps));
  for (std::size_t i = 0; i < o.tiles.size(); ++i) {
    if (o.tiles[i] < 1) throw InputError("", 0, "tile sizes must be positive");
    if (i > 0 && o.tiles[i] > o.tiles[i - 1]) throw InputError("", 0, "tile sizes must decrease");
  }
}

Camera camera_for(const Render3DOptions& o) {
  double yaw = 0, pitch = 0;
  view_angles(o.view, yaw, pitch);
  return make_camera(o.bounds, yaw + o.yaw, pitch + o.pitch, o.size, o.depth_steps, o.z_up);
}

const Vec3f kFacingViewer{0, 0, 1};

Vec3f unit_normal(const Grad& g) {
  const double len = std::sqrt(static_cast<double>(g.dx) * g.dx + static_cast<double>(g.dy) * g.dy +
                               static_cast<double>(g.dz) * g.dz);
  if (!(len > 0) || !std::isfinite(len)) return kFacingViewer;
  return {static_cast<float>(g.dx / len), static_cast<float>(g.dy / len), static_cast<float>(g.dz / len)};
}

// Scratch for locating surfaces: bisection in lockstep over many columns, a final linear
// interpolation, then gradients.
struct Refiner {
  BatchEvaluator batch;
  GradEvaluator grad;
  std::vector<float> us, vs, ws, out, a, b, fa, fb;
  std::vector<Grad> grads;

  void resize(std::size_t n) {
    if (us.size() >= n) return;
    for (auto* v : {&us, &vs, &ws, &out, &a, &b, &fa, &fb}) v->resize(n);
    grads.resize(n);
  }
  // For i < n: column (us[i], vs[i]) is not inside at w = a[i] (value unknown) and inside at
  // w = b[i] with value fb[i] < 0. Bisects `steps` times; then, if the value at the outside end
  // is known, interpolates linearly between the ends, else takes the midpoint: either way within
  // (the sample step) / 2^(steps + 1) of a crossing. Leaves the point in ws[i], its normal in
  // normals[i]. Every operation is per column, so results do not depend on the batch.
  void locate(const Tape& t, std::size_t n, int steps, Vec3f* normals) {
    const float unknown = std::numeric_limits<float>::quiet_NaN();
    std::fill(fa.begin(), fa.begin() + static_cast<std::ptrdiff_t>(n), unknown);
    for (int it = 0; it < steps; ++it) {
      for (std::size_t i = 0; i < n; ++i) ws[i] = 0.5f * (a[i] + b[i]);
      batch.eval(t, us.data(), vs.data(), ws.data(), out.data(), n);
      for (std::size_t i = 0; i < n; ++i) {
        if (out[i] < 0) {
          b[i] = ws[i];
          fb[i] = out[i];
        } else {
          a[i] = ws[i];
          fa[i] = out[i];
        }
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const float d = fa[i] - fb[i];
      if (std::isfinite(fa[i]) && std::isfinite(d) && d > 0)
        ws[i] = std::clamp(a[i] + (b[i] - a[i]) * (fa[i] / d), std::min(a[i], b[i]), std::max(a[i], b[i]));
      else
        ws[i] = 0.5f * (a[i] + b[i]);
    }
    grad.eval(t, us.data(), vs.data(), ws.data(), grads.data(), n);
    for (std::size_t i = 0; i < n; ++i) normals[i] = unit_normal(grads[i]);
    // Where the point lands exactly on the surface, an exact distance such as sqrt(d^2) has
    // gradient 0 by convention (sqrt'(0) = 0): take the normal just outside the surface (a
    // thousandth of the bracket beyond its outside end), else at the outside end (else flat
    // surfaces come out striped where the interpolation hits 0 exactly), else at the inside end.
    for (int stage = 0; stage < 3; ++stage) {
      retry.clear();
      for (std::size_t i = 0; i < n; ++i)
        if (!usable(grads[i])) retry.push_back(static_cast<std::uint32_t>(i));
      if (retry.empty()) return;
      const std::size_t m = retry.size();
      for (auto* v : {&ru, &rv, &rw}) v->resize(m);
      rgrads.resize(m);
      for (std::size_t k = 0; k < m; ++k) {
        const std::uint32_t i = retry[k];
        ru[k] = us[i], rv[k] = vs[i];
        rw[k] = stage == 0 ? a[i] + 1e-3f * (a[i] - b[i]) : stage == 1 ? a[i] : b[i];
      }
      grad.eval(t, ru.data(), rv.data(), rw.data(), rgrads.data(), m);
      for (std::size_t k = 0; k < m; ++k)
        if (usable(rgrads[k])) grads[retry[k]] = rgrads[k], normals[retry[k]] = unit_normal(rgrads[k]);
    }
  }
  static bool usable(const Grad& g) {
    const float l = std::fabs(g.dx) + std::fabs(g.dy) + std::fabs(g.dz);
    return l > 0 && std::isfinite(l);
  }
  std::vector<std::uint32_t> retry;
  std::vector<float> ru, rv, rw;
  std::vector<Grad> rgrads;
};

void atomic_min(int& slot, int v) {
  std::atomic_ref<int> a(slot);
  int cur = a.load(std::memory_order_relaxed);
  while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}
int atomic_load(int& slot) { return std::atomic_ref<int>(slot).load(std::memory_order_relaxed); }

constexpr int kNone = INT_MAX;

constexpr std::uint32_t kNoKey = UINT32_MAX;

}  // namespace

struct Renderer3D::Worker {
  Refiner refiner;
  std::vector<std::uint32_t> active, next;  // pixels still searched in a leaf
  std::vector<int> limit;                   // per active pixel: the last useful sample
  std::vector<std::uint32_t> hit_pixel;     // hits to refine: pixel and sample
  std::vector<int> hit_sample;
  std::vector<float> hit_value;
  std::vector<Vec3f> normals;
};

// Everything one render shares between workers.
struct Renderer3D::State {
  int width = 0;
  std::vector<float> uc, vc, ws;  // pixel centers and depth samples
  std::vector<int> best;          // per pixel: first inside sample known (kNone)
  std::vector<std::uint32_t> key; // per pixel: key of the written result (2 s, or 0 at the front)
  std::vector<float> depth;       // per pixel: the written result
  std::vector<Vec3f> normal;
  std::unique_ptr<std::mutex[]> row_locks;

  void write(std::uint32_t p, std::uint32_t k, float w, Vec3f n) {
    std::lock_guard<std::mutex> lock(row_locks[p / static_cast<std::uint32_t>(width)]);
    if (k >= key[p]) return;
    key[p] = k;
    depth[p] = w;
    normal[p] = n;
  }

  // Hits i < n of `wk`: pixel hit_pixel[i], first inside sample hit_sample[i] (> 0), its value
  // in refiner.fb[i] (NaN if unknown). Locates each crossing in the sample step in front of that
  // sample on tape `t` (valid there) and writes it.
  void refine_hits(Worker& wk, const Tape& t, std::size_t n, int steps) {
    if (n == 0) return;
    Refiner& rf = wk.refiner;
    rf.resize(n);
    if (wk.normals.size() < n) wk.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t p = wk.hit_pixel[i];
      const auto s = static_cast<std::size_t>(wk.hit_sample[i]);
      rf.us[i] = uc[p % static_cast<std::uint32_t>(width)];
      rf.vs[i] = vc[p / static_cast<std::uint32_t>(width)];
      rf.a[i] = ws[s - 1];
      rf.b[i] = ws[s];
    }
    rf.locate(t, n, steps, wk.normals.data());
    for (std::size_t i = 0; i < n; ++i)
      write(wk.hit_pixel[i], 2 * static_cast<std::uint32_t>(wk.hit_sample[i]), rf.ws[i], wk.normals[i]);
  }
};

Renderer3D::Renderer3D(Render3DOptions options) : options_(std::move(options)) {
  check_options(options_);
  camera_ = camera_for(options_);
  SubdivisionOptions so;
  so.tiles = options_.tiles.empty() ? automatic_tiles(camera_) : options_.tiles;
  so.threads = options_.threads;
  // One level breadth first: the driver keeps every frontier box's simplified tape, and in 3D
  // two levels make thousands of them (gigabytes for a million-node expression).
  so.breadth_first_levels = 1;
  // The view is a rotation: distances are the model's. A rotated view is cut at the bounds by
  // max(f, box), and the box's distance has Lipschitz constant 1: with a smaller L for f, boxes
  // would settle from a cut value growing faster than L allows (half a sphere went missing).
  so.lipschitz = options_.lipschitz > 0 && !camera_.axis_aligned ? std::max(options_.lipschitz, 1.0) : options_.lipschitz;
  subdivider_ = std::make_unique<Subdivider>(so);
  for (int i = 0; i < subdivider_->workers(); ++i) workers_.push_back(std::make_unique<Worker>());
}

Renderer3D::~Renderer3D() = default;

namespace {

// A model that is one oracle which intersects rays exactly (a mesh, moved or not): each pixel's
// column is a ray, cut to the bounds, and its first point inside is found exactly instead of by
// samples. The front of the view volume inside the shape shows as facing the viewer, as the
// column search shows it; for rotated views, a ray entering the bounds inside the shape shows
// the face of the bounds it enters through.
DepthMap render_rays(const Oracle& oracle, const Camera& cam, const Box3& bounds, ThreadPool& pool) {
  const std::size_t pixels = static_cast<std::size_t>(cam.width) * static_cast<std::size_t>(cam.height);
  DepthMap out;
  out.camera = cam;
  out.depth.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  out.normal.assign(pixels, Vec3f{0, 0, 0});
  const std::vector<float> uc = Camera::centers(cam.u_edges()), vc = Camera::centers(cam.v_edges());
  const std::vector<float> ws = cam.w_samples();
  const double w0 = ws.front(), length = ws.front() - ws.back();
  const Vec3 dir = -cam.toward;
  const Box3 inside = oracle.inside_box();
  const auto to_view = [&](const Vec3& n) {
    return Vec3f(Vec3{dot(n, cam.right), dot(n, cam.up), dot(n, cam.toward)});
  };
  pool.parallel_for(cam.height, [&](int, int row) {
    for (int col = 0; col < cam.width; ++col) {
      const std::size_t p = static_cast<std::size_t>(row) * static_cast<std::size_t>(cam.width) + static_cast<std::size_t>(col);
      const Vec3 o = cam.to_model(uc[static_cast<std::size_t>(col)], vc[static_cast<std::size_t>(row)], w0);
      // The part of the ray in the bounds (the view volume is the bounds for axis-aligned views).
      double t0 = 0, t1 = length;
      Vec3 entry_normal{0, 0, 1};  // in view coordinates: facing the viewer at the front
      if (!cam.axis_aligned) {
        for (int a = 0; a < 3; ++a) {
          if (dir[a] == 0) {
            if (o[a] < bounds.lo[a] || o[a] > bounds.hi[a]) t0 = INFINITY;
            continue;
          }
          double ta = (bounds.lo[a] - o[a]) / dir[a], tb = (bounds.hi[a] - o[a]) / dir[a];
          Vec3 face{0, 0, 0};
          face[a] = ta < tb ? -1 : 1;  // the outward normal of the face entered first
          if (ta > tb) std::swap(ta, tb);
          if (ta > t0) {
            t0 = ta;
            const Vec3f v = to_view(face);
            entry_normal = {v.x, v.y, v.z};
          }
          t1 = std::min(t1, tb);
        }
        if (!(t0 <= t1)) continue;
      }
      const Vec3 e = o + dir * t0;
      // Inside at the entry? Only a point in the box of the inside can be.
      float f = 1;
      if (inside.empty() || inside.contains(e)) {
        const float ex = static_cast<float>(e.x), ey = static_cast<float>(e.y), ez = static_cast<float>(e.z);
        oracle.values(&ex, &ey, &ez, &f, 1);
      }
      if (f < 0) {
        out.depth[p] = static_cast<float>(w0 - t0);
        out.normal[p] = Vec3f(entry_normal);
        continue;
      }
      const std::optional<Oracle::RayHit> h = oracle.first_hit(e, dir, t1 - t0);
      if (!h) continue;
      out.depth[p] = static_cast<float>(w0 - (t0 + h->t));
      const Vec3f n = to_view(h->normal);
      out.normal[p] = n == Vec3f{0, 0, 0} ? kFacingViewer : n;
    }
  });
  return out;
}

}  // namespace

DepthMap Renderer3D::render(const Tape& model) {
  const Camera& cam = camera_;
  if (model.size() == 1 && model.ssa()[0].op == Op::Oracle) {
    const Oracle& o = model.oracle(model.ssa()[0].value);
    if (o.casts_rays()) return render_rays(o, cam, options_.bounds, subdivider_->pool());
  }
  const Tape tape = view_tape(model, cam, options_.bounds);
  const std::size_t pixels = static_cast<std::size_t>(cam.width) * static_cast<std::size_t>(cam.height);
  State st;
  st.width = cam.width;
  SampleGrid grid;
  grid.cells = true;
  grid.coords[0] = cam.u_edges();
  grid.coords[1] = cam.v_edges();
  grid.coords[2] = cam.w_samples();  // nearest first: the driver visits boxes in index order
  grid.check("view volume");
  st.uc = Camera::centers(grid.coords[0]);
  st.vc = Camera::centers(grid.coords[1]);
  st.ws = grid.coords[2];
  st.best.assign(pixels, kNone);
  st.key.assign(pixels, kNoKey);
  st.depth.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  st.normal.assign(pixels, Vec3f{0, 0, 0});
  st.row_locks = std::make_unique<std::mutex[]>(static_cast<std::size_t>(cam.height));
  const int steps = options_.refine_steps;

  struct Visitor {
    Renderer3D& r;
    State& st;
    int steps;

    std::uint32_t pixel(int col, int row) const { return static_cast<std::uint32_t>(row * st.width + col); }

    bool skip(int, const IndexBox& b) {
      for (int row = b.lo[1]; row < b.hi[1]; ++row)
        for (int col = b.lo[0]; col < b.hi[0]; ++col)
          if (atomic_load(st.best[pixel(col, row)]) > b.lo[2]) return false;
      return true;
    }
    bool settled(int, const IndexBox& b, Interval v) {
      if (v.is_unknown()) return false;
      if (v.lo >= 0) return true;
      if (!(v.hi < 0)) return false;
      // Inside throughout: the box's first sample is inside for all its pixels.
      for (int row = b.lo[1]; row < b.hi[1]; ++row)
        for (int col = b.lo[0]; col < b.hi[0]; ++col) {
          const std::uint32_t p = pixel(col, row);
          atomic_min(st.best[p], b.lo[2]);
          if (b.lo[2] == 0) st.write(p, 0, st.ws[0], kFacingViewer);
        }
      return true;
    }
    void leaf(int wi, const Tape& t, const IndexBox& b) {
      Worker& w = *r.workers_[static_cast<std::size_t>(wi)];
      const int s0 = b.lo[2], s1 = b.hi[2];
      w.active.clear();
      w.limit.clear();
      for (int row = b.lo[1]; row < b.hi[1]; ++row)
        for (int col = b.lo[0]; col < b.hi[0]; ++col) {
          const std::uint32_t p = pixel(col, row);
          const int known = atomic_load(st.best[p]);
          if (known > s0) {
            w.active.push_back(p);
            w.limit.push_back(std::min(known, s1));
          }
        }
      w.hit_pixel.clear();
      w.hit_sample.clear();
      w.hit_value.clear();
      Refiner& rf = w.refiner;
      rf.resize(w.active.size());
      // Sample s0 belongs to the box in front too, which refines a hit there; if this box found
      // it first, the crossing it refines in (s0, s0 + 1) is not the nearest and loses.
      for (int s = s0 == 0 ? 0 : s0 + 1; s <= s1 && !w.active.empty(); ++s) {
        const std::size_t n = w.active.size();
        for (std::size_t i = 0; i < n; ++i) {
          rf.us[i] = st.uc[w.active[i] % static_cast<std::uint32_t>(st.width)];
          rf.vs[i] = st.vc[w.active[i] / static_cast<std::uint32_t>(st.width)];
        }
        std::fill(rf.ws.begin(), rf.ws.begin() + static_cast<std::ptrdiff_t>(n), st.ws[static_cast<std::size_t>(s)]);
        rf.batch.eval(t, rf.us.data(), rf.vs.data(), rf.ws.data(), rf.out.data(), n);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < n; ++i) {
          const std::uint32_t p = w.active[i];
          if (rf.out[i] < 0) {
            atomic_min(st.best[p], s);
            if (s == 0) st.write(p, 0, st.ws[0], kFacingViewer);
            else {
              w.hit_pixel.push_back(p);
              w.hit_sample.push_back(s);
              w.hit_value.push_back(rf.out[i]);
            }
          } else if (s < w.limit[i]) {
            w.active[kept] = p;
            w.limit[kept] = w.limit[i];
            ++kept;
          }
        }
        w.active.resize(kept);
        w.limit.resize(kept);
      }
      // Refine the hits that may still be the nearest.
      std::size_t n = 0;
      for (std::size_t i = 0; i < w.hit_pixel.size(); ++i) {
        const std::uint32_t p = w.hit_pixel[i];
        const int s = w.hit_sample[i];
        if (atomic_load(st.best[p]) < s) continue;
        w.hit_pixel[n] = p;
        w.hit_sample[n] = s;
        rf.fb[n] = w.hit_value[i];
        ++n;
      }
      st.refine_hits(w, t, n, steps);
    }
  } visitor{*this, st, steps};
  subdivider_->run(tape, grid, visitor);

  // A box settled inside by a Lipschitz bound leaves its first sample's crossing to the box in
  // front, which evaluates that sample. The two can disagree: by a rounding on the surface itself
  // (the bound says inside, the evaluator +0), or everywhere when the bound is wrong (a user's
  // --lipschitz, a field whose float evaluation breaks it). Such pixels are refined here, with
  // the whole tape.
  {
    Worker& w = *workers_[0];
    w.hit_pixel.clear();
    w.hit_sample.clear();
    for (std::uint32_t p = 0; p < pixels; ++p)
      if (st.best[p] != kNone && st.key[p] == kNoKey) {
        if (st.best[p] == 0) {
          st.write(p, 0, st.ws[0], kFacingViewer);
        } else {
          w.hit_pixel.push_back(p);
          w.hit_sample.push_back(st.best[p]);
        }
      }
    const std::size_t n = w.hit_pixel.size();
    w.refiner.resize(n);
    std::fill_n(w.refiner.fb.begin(), n, std::numeric_limits<float>::quiet_NaN());  // unknown: no interpolation
    st.refine_hits(w, tape, n, steps);
  }

  DepthMap out;
  out.camera = cam;
  for (std::size_t p = 0; p < pixels; ++p)
    FREP_ASSERT((st.best[p] == kNone) == (st.key[p] == kNoKey), "a pixel with an inside sample has no refined hit");
  out.depth = std::move(st.depth);
  out.normal = std::move(st.normal);
  return out;
}

DepthMap render3d(const Tape& tape, const Render3DOptions& options) {
  Renderer3D r(options);
  return r.render(tape);
}

DepthMap render3d_brute_force(const Tape& model, const Render3DOptions& options, int row_step) {
  check_options(options);
  FREP_ASSERT(row_step >= 1, "row step must be positive");
  const Camera cam = camera_for(options);
  const Tape tape = view_tape(model, cam, options.bounds);
  const std::vector<float> uc = Camera::centers(cam.u_edges()), vc = Camera::centers(cam.v_edges()),
                           ws = cam.w_samples();
  DepthMap out;
  out.camera = cam;
  const std::size_t pixels = static_cast<std::size_t>(cam.width) * static_cast<std::size_t>(cam.height);
  out.depth.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  out.normal.assign(pixels, Vec3f{0, 0, 0});
  Refiner rf;
  BatchEvaluator batch;
  const std::size_t w = static_cast<std::size_t>(cam.width);
  std::vector<float> us(w), vs(w), zs(w), vals(w);
  std::vector<std::uint32_t> active, hits;
  std::vector<int> hit_sample;
  std::vector<float> hit_value;
  std::vector<Vec3f> normals;
  for (int row = 0; row < cam.height; row += row_step) {
    active.resize(w);
    for (std::size_t c = 0; c < w; ++c) active[c] = static_cast<std::uint32_t>(c);
    hits.clear();
    hit_sample.clear();
    hit_value.clear();
    for (int s = 0; s <= cam.depth && !active.empty(); ++s) {
      const std::size_t n = active.size();
      for (std::size_t i = 0; i < n; ++i) us[i] = uc[active[i]];
      std::fill(vs.begin(), vs.begin() + static_cast<std::ptrdiff_t>(n), vc[static_cast<std::size_t>(row)]);
      std::fill(zs.begin(), zs.begin() + static_cast<std::ptrdiff_t>(n), ws[static_cast<std::size_t>(s)]);
      batch.eval(tape, us.data(), vs.data(), zs.data(), vals.data(), n);
      std::size_t kept = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (vals[i] < 0) {
          hits.push_back(active[i]);
          hit_sample.push_back(s);
          hit_value.push_back(vals[i]);
        } else {
          active[kept++] = active[i];
        }
      }
      active.resize(kept);
    }
    rf.resize(hits.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      const std::size_t p = out.index(static_cast<int>(hits[i]), row);
      if (hit_sample[i] == 0) {
        out.depth[p] = ws[0];
        out.normal[p] = kFacingViewer;
        continue;
      }
      hits[n] = hits[i];
      rf.us[n] = uc[hits[i]];
      rf.vs[n] = vc[static_cast<std::size_t>(row)];
      rf.a[n] = ws[static_cast<std::size_t>(hit_sample[i]) - 1];
      rf.b[n] = ws[static_cast<std::size_t>(hit_sample[i])];
      rf.fb[n] = hit_value[i];
      ++n;
    }
    if (n == 0) continue;
    normals.resize(n);
    rf.locate(tape, n, options.refine_steps, normals.data());
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t p = out.index(static_cast<int>(hits[i]), row);
      out.depth[p] = rf.ws[i];
      out.normal[p] = normals[i];
    }
  }
  return out;
}

}  // namespace frep
