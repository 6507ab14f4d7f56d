// Marching squares on a pruned grid: the subdivision driver hands over tiles whose interval
// contains 0 with their simplified tape; each tile finds its cells' crossings, refines them onto
// the zero set along the grid edges (batched regula falsi), adds corner vertices and splits far
// chords, and emits oriented segments keyed by grid edge. The segments are then chained into
// rings: a crossing lies on one grid edge, shared by the two cells that meet there, so every ring
// closes and no two rings cross.
#include "frep/slice/cross_section.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"

namespace frep::slice {
namespace {

constexpr int kMaxCells = 1 << 20;

// Cell corners: 0 = (i, j), 1 = (i + 1, j), 2 = (i + 1, j + 1), 3 = (i, j + 1). Cell edges:
// 0 bottom (corners 0-1), 1 right (1-2), 2 top (3-2), 3 left (0-3).
constexpr double kCornerPos[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
constexpr double kEdgeMid[4][2] = {{0.5, 0}, {1, 0.5}, {0.5, 1}, {0, 0.5}};
constexpr int kEdgeCorners[4][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}};
// The two edges next to each corner.
constexpr int kCornerEdges[4][2] = {{0, 3}, {0, 1}, {1, 2}, {2, 3}};

// How far a point is from the zero set, estimated from its value and in-plane gradient as
// |f| / |grad f|; NaN where that cannot be told (no gradient, or not finite).
double off_zero_set(const Grad& g) {
  const double gl = std::hypot(g.dx, g.dy);
  if (!(gl > 0) || !std::isfinite(gl) || !std::isfinite(g.v)) return NAN;
  return std::fabs(g.v) / gl;
}

// Orders the segment between edges a and b so that `corner` lies on its left if `left`, else on its right.
std::array<int, 2> orient(int a, int b, int corner, bool left) {
  const double px = kEdgeMid[a][0], py = kEdgeMid[a][1];
  const double qx = kEdgeMid[b][0], qy = kEdgeMid[b][1];
  const double rx = kCornerPos[corner][0], ry = kCornerPos[corner][1];
  const double cross = (qx - px) * (ry - py) - (qy - py) * (rx - px);
  return (cross > 0) == left ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a};
}

struct Segment {
  std::uint64_t from = 0, to = 0;  // grid edges of the crossings it joins
  std::uint32_t first = 0, count = 0;  // points added between them (corner, chord splits), in the worker's `extra`
};

}  // namespace

struct CrossSectioner::Impl {
  struct Worker {
    BatchEvaluator batch;
    GradEvaluator grad;
    std::vector<float> xs, ys, zs, out;
    std::vector<Grad> gout;
    std::vector<float> values;
    std::vector<int> local;  // per tile edge: its crossing's index, or -1
    // Results of the current plane.
    std::vector<std::pair<std::uint64_t, Point2>> crossings;
    std::vector<Segment> segments;
    std::vector<Point2> extra;
    float least = INFINITY;  // has_inside: the least value sampled, and where
    Point2 least_at;
  };

  SampleGrid grid;
  int nx = 0, ny = 0;  // cells
  double x0 = 0, y0 = 0, cell = 0;
  std::unique_ptr<Subdivider> subdivider;
  std::vector<std::unique_ptr<Worker>> workers;
  std::atomic<bool> any_inside{false};
  std::atomic<bool> cut{false};  // section(): the shape reached the grid's border
  Point2 region_lo, region_hi;   // the region asked for

  double sx(int i) const { return static_cast<double>(grid.coords[0][static_cast<std::size_t>(i)]); }
  double sy(int j) const { return static_cast<double>(grid.coords[1][static_cast<std::size_t>(j)]); }
  bool border(int i, int j) const { return i == 0 || j == 0 || i == nx || j == ny; }
  // The samples of a tile (its box of cells, corners included), row by row, at height z.
  void tile_samples(Worker& w, const IndexBox& box, float z) const {
    w.xs.clear(), w.ys.clear();
    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
      for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
        w.xs.push_back(grid.coords[0][static_cast<std::size_t>(i)]);
        w.ys.push_back(grid.coords[1][static_cast<std::size_t>(j)]);
      }
    w.zs.assign(w.xs.size(), z);
  }
  std::uint64_t h_edge(int i, int j) const { return (static_cast<std::uint64_t>(j) * static_cast<std::uint64_t>(nx + 1) + static_cast<std::uint64_t>(i)) * 2; }
  std::uint64_t v_edge(int i, int j) const { return h_edge(i, j) + 1; }
};

CrossSectioner::CrossSectioner(const Tape& tape, Point2 lo, Point2 hi, CrossSectionOptions options)
    : tape_(tape), options_(options), impl_(std::make_unique<Impl>()) {
  if (!(options_.cell > 0) || !std::isfinite(options_.cell))
    throw InputError("", 0, "the cross-section cell size must be a finite number > 0");
  if (!(options_.tolerance > 0) || !std::isfinite(options_.tolerance))
    throw InputError("", 0, "the cross-section tolerance must be a finite number > 0");
  if (!std::isfinite(lo.x) || !std::isfinite(lo.y) || !std::isfinite(hi.x) || !std::isfinite(hi.y) || !(hi.x > lo.x) ||
      !(hi.y > lo.y))
    throw InputError("", 0, "the cross-section region must be finite and not empty");
  Impl& m = *impl_;
  const double c = options_.cell;
  const double wx = std::ceil((hi.x - lo.x) / c), wy = std::ceil((hi.y - lo.y) / c);
  if (wx + 2 > kMaxCells || wy + 2 > kMaxCells)
    throw InputError("", 0,
                     "the cross-section region needs more than " + std::to_string(kMaxCells) +
                         " cells along an axis: use larger cells or a smaller region");
  // One cell of margin on each side, so that a shape ending at the region's border still closes
  // on samples of its own.
  m.nx = static_cast<int>(wx) + 2;
  m.ny = static_cast<int>(wy) + 2;
  m.cell = c;
  m.region_lo = lo;
  m.region_hi = hi;
  m.x0 = (lo.x + hi.x) / 2 - c * m.nx / 2.0;
  m.y0 = (lo.y + hi.y) / 2 - c * m.ny / 2.0;
  m.grid.cells = true;
  for (int i = 0; i <= m.nx; ++i) m.grid.coords[0].push_back(static_cast<float>(m.x0 + c * i));
  for (int j = 0; j <= m.ny; ++j) m.grid.coords[1].push_back(static_cast<float>(m.y0 + c * j));
  m.grid.coords[2] = {0.0f, 0.0f};
  m.grid.check("the cross-section");
  SubdivisionOptions so;
  so.tiles = {256, 64, 16, 4};
  so.threads = options_.threads;
  so.lipschitz = options_.lipschitz;
  m.subdivider = std::make_unique<Subdivider>(so);
  for (int w = 0; w < m.subdivider->workers(); ++w) m.workers.push_back(std::make_unique<Impl::Worker>());
}

CrossSectioner::~CrossSectioner() = default;

namespace {

// The visitor finding whether any sample is inside, and otherwise the sample of least value.
struct InsideVisitor {
  CrossSectioner::Impl* m;
  const float z;
  bool skip(int, const IndexBox&) { return m->any_inside.load(std::memory_order_relaxed); }
  bool settled(int, const IndexBox&, Interval v) {
    if (v.hi < 0) m->any_inside.store(true, std::memory_order_relaxed);
    return v.hi < 0 || v.lo >= 0;
  }
  void leaf(int worker, const Tape& tape, const IndexBox& box) {
    auto& w = *m->workers[static_cast<std::size_t>(worker)];
    m->tile_samples(w, box, z);
    w.out.resize(w.xs.size());
    w.batch.eval(tape, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), w.xs.size());
    for (std::size_t k = 0; k < w.out.size(); ++k) {
      const float v = w.out[k];
      if (v < 0) {
        m->any_inside.store(true, std::memory_order_relaxed);
        return;
      }
      if (v < w.least) w.least = v, w.least_at = {w.xs[k], w.ys[k]};
    }
  }
};

}  // namespace

bool CrossSectioner::has_inside(double z) {
  Impl& m = *impl_;
  m.any_inside = false;
  for (auto& w : m.workers) w->least = INFINITY;
  InsideVisitor v{&m, static_cast<float>(z)};
  m.grid.coords[2] = {static_cast<float>(z), static_cast<float>(z)};
  m.subdivider->run(tape_, m.grid, v);
  if (m.any_inside.load()) return true;
  // No sample is inside, but an inside thinner than a cell may pass between them (the plane
  // just above a part's lowest edge or point): descend from the least sample within the plane,
  // in steps of at most a cell, to where f is least.
  const Impl::Worker* best = nullptr;
  for (const auto& w : m.workers)
    if (!best || w->least < best->least) best = w.get();
  if (!best || !std::isfinite(best->least)) return false;
  GradEvaluator grad;
  double px = best->least_at.x, py = best->least_at.y;
  Grad g = grad.eval(tape_, static_cast<float>(px), static_cast<float>(py), static_cast<float>(z));
  double step = m.cell;
  for (int it = 0; it < 40 && g.v >= 0 && step > 1e-7 * m.cell; ++it) {
    const double gl = std::hypot(g.dx, g.dy);
    if (!(gl > 0) || !std::isfinite(gl)) break;
    // Newton's step to f = 0 along the in-plane gradient, capped.
    const double len = std::min(step, 1.5 * g.v / gl);
    const double qx = px - len * g.dx / gl, qy = py - len * g.dy / gl;
    const Grad h = grad.eval(tape_, static_cast<float>(qx), static_cast<float>(qy), static_cast<float>(z));
    if (h.v < g.v) px = qx, py = qy, g = h;
    else step = len / 2;
  }
  return g.v < 0;
}

namespace {

struct SectionVisitor {
  CrossSectioner::Impl* m;
  const CrossSectionOptions* o;
  const float z;

  bool settled(int, const IndexBox& box, Interval v) {
    if (v.lo >= 0) return true;
    // Inside everywhere settles a tile unless it reaches the grid's border, where the contour is closed.
    const bool at_border = box.lo[0] == 0 || box.lo[1] == 0 || box.hi[0] == m->nx || box.hi[1] == m->ny;
    return v.hi < 0 && !at_border;
  }

  void eval(CrossSectioner::Impl::Worker& w, const Tape& tape, std::size_t n) {
    w.zs.assign(n, z);
    w.out.resize(n);
    w.batch.eval(tape, w.xs.data(), w.ys.data(), w.zs.data(), w.out.data(), n);
  }
  void eval_grad(CrossSectioner::Impl::Worker& w, const Tape& tape, std::size_t n) {
    w.zs.assign(n, z);
    w.gout.resize(n);
    w.grad.eval(tape, w.xs.data(), w.ys.data(), w.zs.data(), w.gout.data(), n);
  }

  void leaf(int worker, const Tape& tape, const IndexBox& box) {
    CrossSectioner::Impl& g = *m;
    auto& w = *g.workers[static_cast<std::size_t>(worker)];
    const int i0 = box.lo[0], j0 = box.lo[1];
    const int cx = box.hi[0] - i0, cy = box.hi[1] - j0;  // cells
    const int sxn = cx + 1;
    // Values at the tile's samples; samples on the grid's border count as outside.
    g.tile_samples(w, box, z);
    eval(w, tape, w.xs.size());
    w.values = w.out;
    auto value = [&](int i, int j) { return w.values[static_cast<std::size_t>(j * sxn + i)]; };
    auto inside = [&](int i, int j) { return value(i, j) < 0 && !g.border(i0 + i, j0 + j); };

    // Crossings: tile edges whose ends differ in sign. Local edge index: horizontal (i, j) at
    // j * cx + i, vertical (i, j) after all horizontal ones at j * (cx + 1) + i.
    const int h_count = cx * (cy + 1);
    w.local.assign(static_cast<std::size_t>(h_count + (cx + 1) * cy), -1);
    struct Pending {
      int local;
      double ax, ay, bx, by;  // inside end, outside end
      double s0, s1, f0, f1;  // bracket along a -> b and the values there
      int stuck;              // Illinois: which end stayed last (-1, 0, 1)
      bool done;
      bool placed;  // p is final (a border crossing)
      std::uint64_t key;
      Point2 p;
    };
    std::vector<Pending> cr;
    auto add_crossing = [&](int local, int ia, int ja, int ib, int jb, std::uint64_t key) {
      if (w.local[static_cast<std::size_t>(local)] >= 0) return;
      const bool a_in = inside(ia, ja);
      if (a_in == inside(ib, jb)) return;
      if (!a_in) std::swap(ia, ib), std::swap(ja, jb);
      Pending p{};
      p.local = local;
      p.ax = g.sx(i0 + ia), p.ay = g.sy(j0 + ja), p.bx = g.sx(i0 + ib), p.by = g.sy(j0 + jb);
      p.s0 = 0, p.s1 = 1, p.f0 = value(ia, ja), p.f1 = value(ib, jb);
      p.stuck = -1;
      p.key = key;
      // An outside end on the border that is really inside: the contour runs along the border.
      p.done = p.placed = g.border(i0 + ib, j0 + jb) && !(p.f1 >= 0);
      if (p.placed) {
        p.p = {p.bx, p.by};
        g.cut.store(true, std::memory_order_relaxed);
      }
      w.local[static_cast<std::size_t>(local)] = static_cast<int>(cr.size());
      cr.push_back(p);
    };
    for (int j = 0; j <= cy; ++j)
      for (int i = 0; i < cx; ++i) add_crossing(j * cx + i, i, j, i + 1, j, g.h_edge(i0 + i, j0 + j));
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i <= cx; ++i) add_crossing(h_count + j * (cx + 1) + i, i, j, i, j + 1, g.v_edge(i0 + i, j0 + j));
    if (cr.empty()) return;

    // Regula falsi (Illinois) on every crossing at once, one batch evaluation per round. Each
    // crossing's sequence depends only on its edge, so the two tiles sharing an edge agree.
    for (int round = 0; round < 60; ++round) {
      w.xs.clear(), w.ys.clear();
      std::vector<int> open;
      std::vector<double> at;
      for (int k = 0; k < static_cast<int>(cr.size()); ++k) {
        Pending& p = cr[static_cast<std::size_t>(k)];
        if (p.done) continue;
        const double len = std::hypot(p.bx - p.ax, p.by - p.ay);
        double s = 0.5 * (p.s0 + p.s1);
        if (std::isfinite(p.f0) && std::isfinite(p.f1) && p.f1 > p.f0) {
          const double t = p.s0 + (p.s1 - p.s0) * p.f0 / (p.f0 - p.f1);
          if (t > p.s0 && t < p.s1) s = t;
        }
        const double xs = p.ax + s * (p.bx - p.ax), ys = p.ay + s * (p.by - p.ay);
        const float fx = static_cast<float>(xs), fy = static_cast<float>(ys);
        // Converged once the bracket is below a float's step at these coordinates.
        const double ulp = 4 * std::max(std::nextafter(std::fabs(fx), INFINITY) - std::fabs(fx),
                                        std::nextafter(std::fabs(fy), INFINITY) - std::fabs(fy));
        if ((p.s1 - p.s0) * len <= std::max(ulp, 1e-9 * g.cell)) {
          p.done = true;
          continue;
        }
        open.push_back(k);
        at.push_back(s);
        w.xs.push_back(fx), w.ys.push_back(fy);
      }
      if (open.empty()) break;
      eval(w, tape, open.size());
      for (std::size_t q = 0; q < open.size(); ++q) {
        Pending& p = cr[static_cast<std::size_t>(open[q])];
        const float f = w.out[q];
        // Close enough to the zero set (by the secant's slope): done.
        const double len = std::hypot(p.bx - p.ax, p.by - p.ay);
        const double slope = std::isfinite(p.f0) && std::isfinite(p.f1) ? (p.f1 - p.f0) / std::max((p.s1 - p.s0) * len, 1e-30) : 0;
        if (slope > 0 && std::fabs(f) <= 1e-3 * o->tolerance * slope) {
          p.s0 = p.s1 = at[q], p.f0 = p.f1 = 0;
          p.done = true;
        } else if (f < 0) {
          p.s0 = at[q], p.f0 = f;
          if (p.stuck == 0) p.f1 *= 0.5;
          p.stuck = 0;
        } else if (f == 0) {
          p.s0 = p.s1 = at[q], p.f0 = p.f1 = 0;
          p.done = true;
        } else {
          p.s1 = at[q], p.f1 = f;
          if (p.stuck == 1) p.f0 *= 0.5;
          p.stuck = 1;
        }
      }
    }
    for (Pending& p : cr) {
      if (!p.placed) {
        double s = p.s0;
        if (p.s1 > p.s0 && std::isfinite(p.f0) && std::isfinite(p.f1) && p.f1 > p.f0)
          s = p.s0 + (p.s1 - p.s0) * p.f0 / (p.f0 - p.f1);
        else if (p.s1 > p.s0)
          s = 0.5 * (p.s0 + p.s1);
        p.p = {p.ax + s * (p.bx - p.ax), p.ay + s * (p.by - p.ay)};
      }
      w.crossings.push_back({p.key, p.p});
    }

    // Segments per cell, inside on the left; saddles decided by the cell centre's value.
    struct CellSeg {
      int a, b;  // crossing indices
      int ci, cj;  // the cell (tile-local)
    };
    std::vector<CellSeg> segs;
    std::vector<std::array<int, 3>> saddles;  // cell i, j, case
    auto edge_local = [&](int i, int j, int e) {
      switch (e) {
        case 0: return j * cx + i;
        case 1: return h_count + j * (cx + 1) + i + 1;
        case 2: return (j + 1) * cx + i;
        default: return h_count + j * (cx + 1) + i;
      }
    };
    auto crossing_of = [&](int i, int j, int e) { return w.local[static_cast<std::size_t>(edge_local(i, j, e))]; };
    auto emit = [&](int i, int j, std::array<int, 2> ab) {
      segs.push_back({crossing_of(i, j, ab[0]), crossing_of(i, j, ab[1]), i, j});
    };
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i < cx; ++i) {
        const bool in[4] = {inside(i, j), inside(i + 1, j), inside(i + 1, j + 1), inside(i, j + 1)};
        const int cas = in[0] | in[1] << 1 | in[2] << 2 | in[3] << 3;
        if (cas == 0 || cas == 15) continue;
        if (cas == 5 || cas == 10) {
          saddles.push_back({i, j, cas});
          continue;
        }
        int edges[2], n = 0, ref = -1;
        for (int e = 0; e < 4; ++e)
          if (in[kEdgeCorners[e][0]] != in[kEdgeCorners[e][1]]) edges[n++] = e;
        for (int c = 0; c < 4; ++c)
          if (in[c]) ref = c;
        FREP_ASSERT(n == 2 && ref >= 0, "marching squares: a cell without exactly two crossings");
        emit(i, j, orient(edges[0], edges[1], ref, true));
      }
    if (!saddles.empty()) {
      w.xs.clear(), w.ys.clear();
      for (const auto& s : saddles) {
        w.xs.push_back(static_cast<float>(0.5 * (g.sx(i0 + s[0]) + g.sx(i0 + s[0] + 1))));
        w.ys.push_back(static_cast<float>(0.5 * (g.sy(j0 + s[1]) + g.sy(j0 + s[1] + 1))));
      }
      eval(w, tape, saddles.size());
      for (std::size_t q = 0; q < saddles.size(); ++q) {
        const auto [i, j, cas] = saddles[q];
        const bool centre_in = w.out[q] < 0;
        // Cut off the corners of the centre's opposite kind: with the centre inside, the outside
        // corners (on the segments' right); with it outside, the inside corners (on their left).
        for (int c = 0; c < 4; ++c) {
          const bool corner_in = (cas >> c & 1) != 0;
          if (corner_in == centre_in) continue;
          emit(i, j, orient(kCornerEdges[c][0], kCornerEdges[c][1], c, corner_in));
        }
      }
    }

    // Gradients at the crossings (for corners).
    w.xs.clear(), w.ys.clear();
    for (const Pending& p : cr) w.xs.push_back(static_cast<float>(p.p.x)), w.ys.push_back(static_cast<float>(p.p.y));
    eval_grad(w, tape, cr.size());
    std::vector<Grad> cg = w.gout;

    // Each segment's points: its two crossings with what goes between.
    std::vector<std::vector<Point2>> pts(segs.size());
    for (std::size_t s = 0; s < segs.size(); ++s)
      pts[s] = {cr[static_cast<std::size_t>(segs[s].a)].p, cr[static_cast<std::size_t>(segs[s].b)].p};
    auto cell_lo = [&](const CellSeg& s) { return Point2{g.sx(i0 + s.ci), g.sy(j0 + s.cj)}; };
    auto cell_hi = [&](const CellSeg& s) { return Point2{g.sx(i0 + s.ci + 1), g.sy(j0 + s.cj + 1)}; };

    // True if a sample strictly inside the triangle abc is inside the shape.
    auto sample_inside_triangle = [&](Point2 a, Point2 b, Point2 c) {
      const double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      if (area2 == 0) return false;
      const int ia = std::max(0, static_cast<int>(std::floor((std::min({a.x, b.x, c.x}) - g.sx(i0)) / g.cell)));
      const int ib = std::min(cx, static_cast<int>(std::ceil((std::max({a.x, b.x, c.x}) - g.sx(i0)) / g.cell)));
      const int ja = std::max(0, static_cast<int>(std::floor((std::min({a.y, b.y, c.y}) - g.sy(j0)) / g.cell)));
      const int jb = std::min(cy, static_cast<int>(std::ceil((std::max({a.y, b.y, c.y}) - g.sy(j0)) / g.cell)));
      auto side = [](Point2 p, Point2 q, double x, double y) { return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x); };
      for (int j = ja; j <= jb; ++j)
        for (int i = ia; i <= ib; ++i) {
          const double x = g.sx(i0 + i), y = g.sy(j0 + j);
          const double s1 = side(a, b, x, y), s2 = side(b, c, x, y), s3 = side(c, a, x, y);
          const bool in = area2 > 0 ? (s1 > 0 && s2 > 0 && s3 > 0) : (s1 < 0 && s2 < 0 && s3 < 0);
          if (in && inside(i, j)) return true;
        }
      return false;
    };

    // Corners: where the normals at a segment's ends differ, the tangents' meeting point, if it
    // is inside the cell and on the zero set.
    if (o->corner_cosine < 1) {
      std::vector<std::size_t> cand;
      std::vector<Point2> at;
      for (std::size_t s = 0; s < segs.size(); ++s) {
        const Grad& ga = cg[static_cast<std::size_t>(segs[s].a)];
        const Grad& gb = cg[static_cast<std::size_t>(segs[s].b)];
        const double la = std::hypot(ga.dx, ga.dy), lb = std::hypot(gb.dx, gb.dy);
        if (!(la > 0) || !(lb > 0) || !std::isfinite(la) || !std::isfinite(lb)) continue;
        const double ax = ga.dx / la, ay = ga.dy / la, bx = gb.dx / lb, by = gb.dy / lb;
        if (ax * bx + ay * by >= o->corner_cosine) continue;
        const double det = ax * by - ay * bx;
        if (std::fabs(det) < 1e-6) continue;
        const Point2 pa = pts[s][0], pb = pts[s][1];
        const double ra = ax * pa.x + ay * pa.y, rb = bx * pb.x + by * pb.y;
        const Point2 x{(ra * by - rb * ay) / det, (ax * rb - bx * ra) / det};
        // The corner may lie beyond the cell: the tip of a notch narrower than a cell passes
        // between samples. Accept it within a few cells and in the tile (where the tape is
        // valid) if no sample inside the triangle it adds is inside the shape.
        const Point2 lo = cell_lo(segs[s]), hi = cell_hi(segs[s]);
        const double reach = 4 * g.cell;
        if (!(x.x >= std::max(lo.x - reach, g.sx(i0)) && x.x <= std::min(hi.x + reach, g.sx(i0 + cx)) &&
              x.y >= std::max(lo.y - reach, g.sy(j0)) && x.y <= std::min(hi.y + reach, g.sy(j0 + cy))))
          continue;
        if (!(x.x >= lo.x && x.x <= hi.x && x.y >= lo.y && x.y <= hi.y) && sample_inside_triangle(pa, x, pb)) continue;
        cand.push_back(s);
        at.push_back(x);
      }
      if (!cand.empty()) {
        w.xs.clear(), w.ys.clear();
        for (const Point2& p : at) w.xs.push_back(static_cast<float>(p.x)), w.ys.push_back(static_cast<float>(p.y));
        eval_grad(w, tape, cand.size());
        for (std::size_t q = 0; q < cand.size(); ++q) {
          const Grad& gq = w.gout[q];
          const double gl = std::max<double>(std::hypot(gq.dx, gq.dy), 1e-3);
          if (std::fabs(gq.v) / gl <= o->tolerance) pts[cand[q]].insert(pts[cand[q]].begin() + 1, at[q]);
        }
      }
    }

    // Chords: a midpoint farther than the tolerance from the zero set is moved onto it (Newton
    // steps along the gradient) and splits the chord if it lands in the cell and on the zero set.
    std::vector<std::vector<char>> checked(segs.size());
    for (std::size_t s = 0; s < segs.size(); ++s) {
      checked[s].assign(pts[s].size() - 1, 0);
      if (pts[s].size() != 2) continue;
      // A chord whose ends' normals turn by an angle t bulges from an arc by about its length
      // times t / 8: nothing to check when that is well within the tolerance.
      const Grad& ga = cg[static_cast<std::size_t>(segs[s].a)];
      const Grad& gb = cg[static_cast<std::size_t>(segs[s].b)];
      const double la = std::hypot(ga.dx, ga.dy), lb = std::hypot(gb.dx, gb.dy);
      if (!(la > 0) || !(lb > 0) || !std::isfinite(la) || !std::isfinite(lb)) continue;
      const double c = std::clamp((ga.dx * gb.dx + ga.dy * gb.dy) / (la * lb), -1.0, 1.0);
      const double chord = std::hypot(pts[s][1].x - pts[s][0].x, pts[s][1].y - pts[s][0].y);
      if (chord * std::acos(c) / 8 <= 0.25 * o->tolerance) checked[s][0] = 1;
    }
    auto newton = [](Point2 p, const Grad& gq, bool& ok) {
      const double gl2 = static_cast<double>(gq.dx) * gq.dx + static_cast<double>(gq.dy) * gq.dy;
      ok = gl2 > 0 && std::isfinite(gl2) && std::isfinite(gq.v);
      return ok ? Point2{p.x - gq.v * gq.dx / gl2, p.y - gq.v * gq.dy / gl2} : p;
    };
    for (int round = 0; round < 3; ++round) {
      // The chords not checked yet, by segment and index at the start of the round.
      std::vector<std::pair<std::size_t, std::size_t>> chords;
      w.xs.clear(), w.ys.clear();
      for (std::size_t s = 0; s < segs.size(); ++s)
        for (std::size_t k = 0; k + 1 < pts[s].size(); ++k) {
          if (checked[s][k]) continue;
          checked[s][k] = 1;
          chords.push_back({s, k});
          w.xs.push_back(static_cast<float>(0.5 * (pts[s][k].x + pts[s][k + 1].x)));
          w.ys.push_back(static_cast<float>(0.5 * (pts[s][k].y + pts[s][k + 1].y)));
        }
      if (chords.empty()) break;
      eval_grad(w, tape, chords.size());
      // Chords whose midpoints are off (indices into `chords`), and their points as Newton moves them.
      std::vector<std::size_t> off;
      std::vector<Point2> at;
      for (std::size_t q = 0; q < chords.size(); ++q) {
        const Grad& gq = w.gout[q];
        const double away = off_zero_set(gq);
        if (std::isnan(away) || away <= o->tolerance) continue;
        bool ok = false;
        const Point2 p = newton({w.xs[q], w.ys[q]}, gq, ok);
        if (ok) off.push_back(q), at.push_back(p);
      }
      // Up to two more Newton steps; a point that lands in its cell on the zero set splits its chord.
      std::vector<std::pair<std::size_t, Point2>> splits;  // (index into `chords`, the new point)
      for (int step = 0; step < 2 && !off.empty(); ++step) {
        w.xs.clear(), w.ys.clear();
        for (const Point2& p : at) w.xs.push_back(static_cast<float>(p.x)), w.ys.push_back(static_cast<float>(p.y));
        eval_grad(w, tape, at.size());
        std::vector<std::size_t> next_off;
        std::vector<Point2> next_at;
        for (std::size_t q = 0; q < off.size(); ++q) {
          const Grad& gq = w.gout[q];
          const Point2 p{w.xs[q], w.ys[q]};
          const std::size_t s = chords[off[q]].first;
          const Point2 lo = cell_lo(segs[s]), hi = cell_hi(segs[s]);
          if (!(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y)) continue;  // left its cell: keep the chord
          if (off_zero_set(gq) <= 0.5 * o->tolerance) {
            splits.push_back({off[q], p});
            continue;
          }
          bool ok = false;
          const Point2 np = newton(p, gq, ok);
          if (ok && step == 0) next_off.push_back(off[q]), next_at.push_back(np);
        }
        off = std::move(next_off);
        at = std::move(next_at);
      }
      // Insert the splits from each segment's last chord to its first, so that the indices taken
      // at the start of the round stay right; the two halves of a split chord get checked next round.
      std::sort(splits.begin(), splits.end(), [&](const auto& x, const auto& y) {
        return chords[x.first] > chords[y.first];
      });
      for (const auto& [c, p] : splits) {
        const auto [s, k] = chords[c];
        pts[s].insert(pts[s].begin() + static_cast<std::ptrdiff_t>(k) + 1, p);
        checked[s].insert(checked[s].begin() + static_cast<std::ptrdiff_t>(k) + 1, 0);
        checked[s][k] = 0;
      }
    }

    for (std::size_t s = 0; s < segs.size(); ++s) {
      Segment out;
      out.from = cr[static_cast<std::size_t>(segs[s].a)].key;
      out.to = cr[static_cast<std::size_t>(segs[s].b)].key;
      out.first = static_cast<std::uint32_t>(w.extra.size());
      out.count = static_cast<std::uint32_t>(pts[s].size() - 2);
      w.extra.insert(w.extra.end(), pts[s].begin() + 1, pts[s].end() - 1);
      w.segments.push_back(out);
    }
  }
};

}  // namespace

Region CrossSectioner::section(double z) {
  Impl& m = *impl_;
  for (auto& w : m.workers) w->crossings.clear(), w->segments.clear(), w->extra.clear();
  m.cut = false;
  m.grid.coords[2] = {static_cast<float>(z), static_cast<float>(z)};
  SectionVisitor v{&m, &options_, static_cast<float>(z)};
  m.subdivider->run(tape_, m.grid, v);

  // Chain the segments into rings.
  std::unordered_map<std::uint64_t, Point2> point;
  struct Ref {
    std::uint32_t worker, index;
  };
  std::unordered_map<std::uint64_t, Ref> from;
  std::size_t total = 0;
  for (const auto& w : m.workers) total += w->segments.size();
  point.reserve(total);
  from.reserve(total);
  for (std::uint32_t wi = 0; wi < m.workers.size(); ++wi) {
    const auto& w = *m.workers[wi];
    for (const auto& [key, p] : w.crossings) point.emplace(key, p);
    for (std::uint32_t s = 0; s < w.segments.size(); ++s) {
      const bool fresh = from.emplace(w.segments[s].from, Ref{wi, s}).second;
      FREP_ASSERT(fresh, "marching squares: two segments leave one crossing");
    }
  }
  // Rings start at their smallest edge key, and come in that order: the output does not depend
  // on which worker found what.
  std::vector<std::uint64_t> starts;
  starts.reserve(from.size());
  for (const auto& kv : from) starts.push_back(kv.first);
  std::sort(starts.begin(), starts.end());
  Region rings;
  std::unordered_map<std::uint64_t, char> used;
  used.reserve(total);
  for (const std::uint64_t start : starts) {
    if (used.count(start)) continue;
    Ring ring;
    std::uint64_t key = start;
    for (;;) {
      FREP_ASSERT(key == start || !used.count(key), "marching squares: two segments enter one crossing");
      used.emplace(key, 1);
      const auto it = from.find(key);
      // A contour that stops can only come from a tile settled as all inside or all outside
      // where the zero set crosses it: a Lipschitz bound smaller than the field's.
      if (it == from.end())
        throw InputError("", 0,
                         "the cross-section at z = " + std::to_string(z) +
                             " does not close: the field changes faster than the Lipschitz bound used (" +
                             std::to_string(options_.lipschitz) + ") allows; give a larger --lipschitz, or 0");
      const auto& w = *m.workers[it->second.worker];
      const Segment& s = w.segments[it->second.index];
      ring.push_back(point.at(key));
      for (std::uint32_t k = 0; k < s.count; ++k) ring.push_back(w.extra[s.first + k]);
      key = s.to;
      if (key == start) break;
    }
    ring = simplify(ring, options_.tolerance * 0.5, true);
    if (ring.size() >= 3) rings.push_back(std::move(ring));
  }
  if (!m.cut.load()) return normalize(rings);
  // Cut by the grid's border, a cell outside the region: cut at the region itself.
  const Point2 lo = m.region_lo, hi = m.region_hi;
  return intersect(rings, {{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}});
}

Region cross_section(const Tape& tape, double z, Point2 lo, Point2 hi, const CrossSectionOptions& options) {
  CrossSectioner s(tape, lo, hi, options);
  return s.section(z);
}

}  // namespace frep::slice
