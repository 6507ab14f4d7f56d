// Error-bounded simplification (simplify.hpp): Garland-Heckbert quadrics order half-edge
// collapses in a lazy priority queue; a collapse is applied only if four checks all hold.
#include "contour/simplify.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <mutex>
#include <queue>
#include <unordered_map>
#include <vector>

#include "frep/contour/mesh_options.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/util/thread_pool.hpp"
#include "util/union_find.hpp"

namespace frep::contour {
namespace {

// Sum of squared distances to planes, area-weighted: q(p) = p.A.p + 2 b.p + c.
struct Quadric {
  double a[6] = {0, 0, 0, 0, 0, 0};  // xx xy xz yy yz zz
  double b[3] = {0, 0, 0};
  double c = 0;
  void add_plane(const Vec3& n, double d, double w) {
    a[0] += w * n.x * n.x, a[1] += w * n.x * n.y, a[2] += w * n.x * n.z;
    a[3] += w * n.y * n.y, a[4] += w * n.y * n.z, a[5] += w * n.z * n.z;
    b[0] += w * n.x * d, b[1] += w * n.y * d, b[2] += w * n.z * d;
    c += w * d * d;
  }
  void add(const Quadric& o) {
    for (int i = 0; i < 6; ++i) a[i] += o.a[i];
    for (int i = 0; i < 3; ++i) b[i] += o.b[i];
    c += o.c;
  }
  double at(const Vec3& p) const {
    return a[0] * p.x * p.x + 2 * a[1] * p.x * p.y + 2 * a[2] * p.x * p.z + a[3] * p.y * p.y +
           2 * a[4] * p.y * p.z + a[5] * p.z * p.z + 2 * (b[0] * p.x + b[1] * p.y + b[2] * p.z) + c;
  }
};

struct Candidate {
  double cost, len2;
  std::uint32_t u, v;  // u collapses onto v (v stays, at its position)
  std::uint32_t version;  // v's version when queued
  bool operator>(const Candidate& o) const {
    if (cost != o.cost) return cost > o.cost;
    if (len2 != o.len2) return len2 > o.len2;
    if (u != o.u) return u > o.u;
    return v > o.v;
  }
};

// One 64-bit key for cell (i, j, k): 21 bits per axis (the spatial hash's cells wrap around at
// 2^21; region coordinates stay below it).
std::uint64_t cell_key(std::int64_t i, std::int64_t j, std::int64_t k) {
  return (static_cast<std::uint64_t>(i & 0x1fffff) << 42) | (static_cast<std::uint64_t>(j & 0x1fffff) << 21) |
         static_cast<std::uint64_t>(k & 0x1fffff);
}

// 4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle, 0 for a flat one.
double quality(const Vec3& p, const Vec3& q, const Vec3& r) {
  const double e = length2(q - p) + length2(r - q) + length2(p - r);
  return e > 0 ? 2 * std::sqrt(3.0) * length(cross(q - p, r - p)) / e : 0;
}

// What one Simplifier works on: a whole mesh, or one region of it with the triangles around it.
struct Part {
  std::vector<Vec3> P;
  std::vector<Triangle> T;
  std::vector<double> scale;         // per vertex: min(1, |grad f|), which scales E into a bound on |f|
  std::vector<float> value;          // per vertex: f there
  std::vector<Quadric> Q;            // per vertex: its quadric
  std::vector<std::uint32_t> shell;  // per vertex: its shell's index into `volume`
  std::vector<double> volume;        // per shell: signed volume
  // Per shell: the most total |volume change| allowed here (a shell other regions change too), or
  // infinite (only its sign is kept).
  std::vector<double> budget;
  std::vector<char> frozen;  // per vertex: never removed nor collapsed onto (its star is not all here)
  std::vector<char> seed;    // per vertex: its edges are queued at the start; empty: every edge
};

class Simplifier {
 public:
  Simplifier(Part&& part, const Tape& tape, double max_error, double cell)
      : P_(std::move(part.P)), T_(std::move(part.T)), tape_(tape), E_(max_error), cell_(cell),
        scale_(std::move(part.scale)), fvertex_(std::move(part.value)), Q_(std::move(part.Q)), frozen_(std::move(part.frozen)),
        shell_(std::move(part.shell)), volume_(std::move(part.volume)), budget_(std::move(part.budget)) {
    alive_.assign(T_.size(), 1);
    vdead_.assign(P_.size(), 0);
    vtris_.resize(P_.size());
    version_.assign(P_.size(), 0);
    mark_.assign(T_.size(), 0);
    held_.assign(T_.size(), INFINITY);
    pending_.assign(P_.size(), 0);
    spent_.assign(volume_.size(), 0);
    hash_size_ = 4 * cell_;
    for (std::uint32_t t = 0; t < T_.size(); ++t) {
      for (int k = 0; k < 3; ++k) vtris_[T_[t][k]].push_back(t);
      hash_insert(t);
    }
    for (std::uint32_t t = 0; t < T_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = T_[t][k], b = T_[t][(k + 1) % 3];
        if (a > b) continue;  // each edge once (the other triangle has b -> a)
        if (!part.seed.empty() && !part.seed[a] && !part.seed[b]) continue;
        push(a, b), push(b, a);
      }
  }

  void run(SimplifyReport& rep) {
    while (!heap_.empty()) {
      const Candidate c = heap_.top();
      heap_.pop();
      if (vdead_[c.u] || vdead_[c.v] || c.version != version_[c.v]) continue;
      if (!try_collapse(c.u, c.v)) {
        ++rep.rejected;
        continue;
      }
      ++rep.collapses;
    }
  }

  // After run: the triangles, whether each is still there, the vertices' quadrics, and the
  // vertices with collapses left to try: frozen ones with an edge never tried, and both ends of
  // collapses refused only for the volume budget.
  const std::vector<Triangle>& triangles() const { return T_; }
  bool alive(std::uint32_t t) const { return alive_[t]; }
  const Quadric& quadric(std::uint32_t v) const { return Q_[v]; }
  bool pending(std::uint32_t v) const { return pending_[v]; }

 private:
  std::vector<Vec3> P_;
  std::vector<Triangle> T_;
  const Tape& tape_;
  double E_, cell_, hash_size_;
  std::vector<double> scale_;  // as Part
  std::vector<float> fvertex_;  // Part::value
  std::vector<Quadric> Q_;
  std::vector<char> frozen_;
  std::vector<std::uint32_t> shell_;
  std::vector<double> volume_, budget_;
  std::vector<double> spent_;  // per shell: total |volume change| so far
  std::vector<char> alive_, vdead_, pending_;
  std::vector<std::vector<std::uint32_t>> vtris_;
  std::vector<std::uint32_t> version_, mark_;
  // Per triangle: the largest |f| at its samples, or at the samples of the triangles whose
  // region it re-triangulates (infinite: never sampled).
  std::vector<double> held_;
  std::vector<std::pair<Triangle, double>> checks_;  // triangles to sample, with their limits
  struct EdgeCheck {
    std::uint32_t a, b;  // a < b
    int n;               // sample intervals along it
    double limit;
    std::uint32_t check;  // the listed triangle it is an edge of
    std::uint32_t group;  // its index among the distinct edges
  };
  std::vector<EdgeCheck> edges_;   // the listed triangles' edges (triangles_within)
  std::vector<std::int32_t> owner_;  // per sample: its listed triangle, or -1 - its edge group
  std::vector<float> edge_max_;     // per edge group: the largest |f| at its samples
  std::vector<float> maxima_;       // per listed triangle, after triangles_within held: the largest |f| at its samples
  std::uint32_t stamp_ = 0;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap_;
  // Spatial hash: per cell, entries (triangle << 32 | its version when inserted). A triangle that
  // moves gets a new version and new entries; old ones are dropped when their cell is next read.
  std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> hash_;
  std::vector<std::uint32_t> tver_;  // per triangle: its version
  BatchEvaluator eval_;
  std::vector<float> xs_, ys_, zs_, out_;
  std::vector<double> limit_;  // per sample: the bound on |f| of its triangle

  void push(std::uint32_t u, std::uint32_t v) {
    if (frozen_[u] || frozen_[v]) {
      pending_[u] |= frozen_[u], pending_[v] |= frozen_[v];
      return;
    }
    Quadric q = Q_[u];
    q.add(Q_[v]);
    heap_.push({std::max(0.0, q.at(P_[v])), length2(P_[u] - P_[v]), u, v, version_[v]});
  }

  std::array<std::int64_t, 3> hash_cell(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x / hash_size_)), static_cast<std::int64_t>(std::floor(p.y / hash_size_)),
            static_cast<std::int64_t>(std::floor(p.z / hash_size_))};
  }
  Box3 box_of(const std::array<Vec3, 3>& c) const {
    Box3 b;
    for (const Vec3& p : c) b.add(p);
    return b;
  }
  std::array<Vec3, 3> corners(std::uint32_t t) const { return {P_[T_[t][0]], P_[T_[t][1]], P_[T_[t][2]]}; }
  template <class F>
  void for_cells(const Box3& b, F&& f) const {
    const auto lo = hash_cell(b.lo), hi = hash_cell(b.hi);
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k) f(cell_key(i, j, k));
  }
  // (Re)inserts triangle t at its current corners under a new version.
  void hash_insert(std::uint32_t t) {
    if (tver_.size() <= t) tver_.resize(T_.size(), 0);
    const std::uint64_t entry = static_cast<std::uint64_t>(t) << 32 | ++tver_[t];
    for_cells(box_of(corners(t)), [&](std::uint64_t k) { hash_[k].push_back(entry); });
  }
  // The current triangles a cell's list holds (dropping entries of triangles that died or moved
  // since, which would otherwise pile up as collapses move triangles about).
  std::vector<std::uint64_t>& live_entries(std::vector<std::uint64_t>& list) {
    std::size_t w = 0;
    for (const std::uint64_t e : list) {
      const std::uint32_t t = static_cast<std::uint32_t>(e >> 32);
      if (alive_[t] && tver_[t] == static_cast<std::uint32_t>(e)) list[w++] = e;
    }
    list.resize(w);
    return list;
  }

  // The vertices of v's triangles (v among them), sorted and distinct, into `out`.
  void ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t t : vtris_[v])
      for (int k = 0; k < 3; ++k) out.push_back(T_[t][k]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  bool try_collapse(std::uint32_t u, std::uint32_t v) {
    // (1) Topology: the edge has its two triangles, with opposite corners a != b; u and v share
    // no other neighbour (the link condition: the result stays a manifold); a and b keep at least
    // three triangles (no pinched tetrahedra or flat pockets).
    std::uint32_t opp[2];
    int n_edge = 0;
    for (std::uint32_t t : vtris_[u]) {
      const Triangle& tr = T_[t];
      if (tr[0] != v && tr[1] != v && tr[2] != v) continue;
      if (n_edge == 2) return false;
      for (int k = 0; k < 3; ++k)
        if (tr[k] != u && tr[k] != v) opp[n_edge] = tr[k];
      ++n_edge;
    }
    if (n_edge != 2 || opp[0] == opp[1]) return false;
    if (vtris_[opp[0]].size() < 4 || vtris_[opp[1]].size() < 4) return false;
    ++stamp_;
    ring(u, nbr_u_);
    ring(v, nbr_v_);
    int shared = 0;
    for (std::uint32_t w : nbr_v_)
      if (w != u && w != v && std::binary_search(nbr_u_.begin(), nbr_u_.end(), w)) ++shared;
    if (shared != 2) return false;

    // (2) No flips and no slivers: every moved triangle keeps its normal within 60 degrees, a
    // non-zero area, and a shape no worse than min(0.05, its old quality).
    moved_.clear();
    for (std::uint32_t t : vtris_[u]) {
      mark_[t] = stamp_;  // the triangles changed or removed: not candidates for crossings
      const Triangle& tr = T_[t];
      if (tr[0] == v || tr[1] == v || tr[2] == v) continue;
      Triangle nt = tr;
      for (auto& x : nt)
        if (x == u) x = v;
      const Vec3 n0 = cross(P_[tr[1]] - P_[tr[0]], P_[tr[2]] - P_[tr[0]]);
      const Vec3 n1 = cross(P_[nt[1]] - P_[nt[0]], P_[nt[2]] - P_[nt[0]]);
      const double l0 = length(n0), l1 = length(n1);
      if (!(l1 > 0) || !(dot(n0, n1) >= 0.5 * l0 * l1)) return false;
      const double q0 = quality(P_[tr[0]], P_[tr[1]], P_[tr[2]]);
      if (quality(P_[nt[0]], P_[nt[1]], P_[nt[2]]) < std::min(0.05, q0)) return false;
      moved_.push_back({t, nt});
    }

    // (2b) The shell keeps the sign of its volume. The old and new stars share their boundary,
    // so the change is the same from any origin: v's position keeps it accurate.
    double change = 0;
    const Vec3 o = P_[v];
    for (std::uint32_t t : vtris_[u]) {
      const Triangle& tr = T_[t];
      change -= dot(P_[tr[0]] - o, cross(P_[tr[1]] - o, P_[tr[2]] - o)) / 6;
    }
    for (const auto& [t, nt] : moved_) change += dot(P_[nt[0]] - o, cross(P_[nt[1]] - o, P_[nt[2]] - o)) / 6;
    const std::uint32_t shell = shell_[v];
    const double before = volume_[shell], after = before + change;
    if (!(after != 0) || (after > 0) != (before > 0)) return false;
    // A shell other regions change at the same time: this region's changes stay within its share
    // of half the volume, so that together they cannot turn it inside out.
    if (!(spent_[shell] + std::fabs(change) <= budget_[shell])) {
      pending_[u] = pending_[v] = 1;
      return false;
    }

    // A few samples first (corners, edge midpoints, centroid): most refusals are found there,
    // before the costlier crossing test and the full grid of samples.
    // A flat star (u's triangles in one plane, as on the faces of CAD parts), or two along a
    // straight crease, is re-triangulated in place: without flips the new triangles cover
    // exactly the old ones' points, which were within the bound already, so the field needs no
    // samples there.
    double star_limit = INFINITY;  // the strictest limit of the new triangles
    for (const auto& [t, nt] : moved_) star_limit = std::min(star_limit, limit_of(nt));
    const bool flat = (star_is_flat(u) || star_is_crease(u, v)) && star_within(u, star_limit);
    if (!flat && !samples_within(2)) return false;
    double star_held = 0;  // a flat star's: the largest |f| found on its triangles
    if (flat)
      for (std::uint32_t t : vtris_[u]) star_held = std::max(star_held, held_[t]);

    // (4) No crossing, overlap or touching: each new triangle against the triangles near it
    // (exact predicate), and against the other new ones.
    for (std::size_t i = 0; i < moved_.size(); ++i) {
      const Triangle& nt = moved_[i].second;
      const Vec3 p[3] = {P_[nt[0]], P_[nt[1]], P_[nt[2]]};
      const unsigned pi[3] = {nt[0], nt[1], nt[2]};
      for (std::size_t j = 0; j < i; ++j) {
        const Triangle& ot = moved_[j].second;
        const Vec3 q[3] = {P_[ot[0]], P_[ot[1]], P_[ot[2]]};
        const unsigned qi[3] = {ot[0], ot[1], ot[2]};
        if (classify_triangle_pair(p, pi, q, qi) != Contact::None) return false;
      }
      const Box3 b = box_of({p[0], p[1], p[2]});
      bool bad = false;
      ++qstamp_;
      for_cells(b, [&](std::uint64_t k) {
        if (bad) return;
        const auto it = hash_.find(k);
        if (it == hash_.end()) return;
        for (const std::uint64_t e : live_entries(it->second)) {
          const std::uint32_t c = static_cast<std::uint32_t>(e >> 32);
          if (mark_[c] == stamp_) continue;
          if (seen_.size() < T_.size()) seen_.resize(T_.size(), 0);
          if (seen_[c] == qstamp_) continue;
          seen_[c] = qstamp_;
          const auto cc = corners(c);
          const Box3 cb = box_of(cc);
          if (cb.lo.x > b.hi.x || cb.lo.y > b.hi.y || cb.lo.z > b.hi.z || b.lo.x > cb.hi.x || b.lo.y > cb.hi.y ||
              b.lo.z > cb.hi.z)
            continue;
          const Vec3 q[3] = {cc[0], cc[1], cc[2]};
          const unsigned qi[3] = {T_[c][0], T_[c][1], T_[c][2]};
          if (classify_triangle_pair(p, pi, q, qi) != Contact::None) {
            bad = true;
            return;
          }
        }
      });
      if (bad) return false;
    }

    // (3) The error bound: |f| <= 0.9 max_error (times the corners' gradient scale) at points of every new triangle on a barycentric
    // grid at most half a cell apart (its corners included). This is a sampled bound, not a
    // certificate: with a Lipschitz constant L, |f| <= max_error + L * h anywhere on the
    // triangle, h the distance to the nearest sample (under half a cell). On flat faces f is
    // linear along the triangle and the samples bound it; on curved ones the chord's sag between
    // samples is second order, and the 10% margin covers it (without it, random points exceeded
    // the bound by up to 8% on fandisk; with it, none did in the tests).
    if (!flat && !samples_within(64)) return false;

    // Apply.
    for (std::uint32_t t : vtris_[u]) {
      const Triangle& tr = T_[t];
      if (tr[0] != v && tr[1] != v && tr[2] != v) continue;
      alive_[t] = 0;
      for (int k = 0; k < 3; ++k)
        if (tr[k] != u) {
          auto& l = vtris_[tr[k]];
          l.erase(std::find(l.begin(), l.end(), t));
        }
    }
    // What the new triangles are known to hold: what their samples found (samples_within(64)
    // above, in moved_ order), or what the flat star's triangles held.
    for (std::size_t i = 0; i < moved_.size(); ++i) {
      const auto& [t, nt] = moved_[i];
      held_[t] = flat ? star_held : maxima_[i];
      T_[t] = nt;
      vtris_[v].push_back(t);
      hash_insert(t);
    }
    vtris_[u].clear();
    vtris_[u].shrink_to_fit();
    vdead_[u] = 1;
    Q_[v].add(Q_[u]);
    volume_[shell] = after;
    spent_[shell] += std::fabs(change);
    ++version_[v];
    ring(v, nbr_v_);
    for (std::uint32_t w : nbr_v_)
      if (w != v) push(w, v), push(v, w);
    return true;
  }

  // True if u's triangles lie in two planes (each within a millionth of a cell) that meet along a
  // line through v, u and one other vertex of u's ring, with u between the two: a vertex on a
  // straight crease collapsing along it. Each plane's triangles are then a flat star of their
  // own, re-triangulated in place (their region is the same with u gone from the straight edge).
  // Reads u's ring from nbr_u_ (try_collapse's link check fills it).
  bool star_is_crease(std::uint32_t u, std::uint32_t v) const {
    const double tol = 1e-6 * cell_;
    const Vec3 o = P_[u];
    Vec3 n[2];
    int planes = 0;
    auto in_plane = [&](const Triangle& tr, const Vec3& nn) {
      for (int k = 0; k < 3; ++k)
        if (std::fabs(dot(P_[tr[k]] - o, nn)) > tol) return false;
      return true;
    };
    for (std::uint32_t t : vtris_[u]) {
      const Triangle& tr = T_[t];
      if (planes > 0 && in_plane(tr, n[0])) continue;
      if (planes > 1 && in_plane(tr, n[1])) continue;
      if (planes == 2) return false;
      const Vec3 c = cross(P_[tr[1]] - P_[tr[0]], P_[tr[2]] - P_[tr[0]]);
      const double len = length(c);
      if (!(len > 0)) return false;
      n[planes++] = c / len;
    }
    if (planes != 2) return false;
    Vec3 d = cross(n[0], n[1]);
    const double dl = length(d);
    if (!(dl > 1e-3)) return false;  // nearly one plane: not a crease to rely on
    d = d / dl;
    // The ring's vertices on the line through u along the crease: exactly v and one more, on
    // opposite sides of u.
    int on_line = 0;
    bool has_v = false;
    double side_v = 0, side_w = 0;
    for (std::uint32_t w : nbr_u_) {
      if (w == u) continue;
      const Vec3 r = P_[w] - o;
      const double along = dot(r, d);
      if (length(r - d * along) > tol) continue;
      ++on_line;
      if (w == v) has_v = true, side_v = along;
      else side_w = along;
    }
    return on_line == 2 && has_v && side_v * side_w < 0;
  }

  // True if every vertex of u's triangles lies within a millionth of a cell of the plane
  // through u along their area-weighted normal.
  bool star_is_flat(std::uint32_t u) const {
    Vec3 n{0, 0, 0};
    for (std::uint32_t t : vtris_[u]) {
      const Triangle& tr = T_[t];
      n = n + cross(P_[tr[1]] - P_[tr[0]], P_[tr[2]] - P_[tr[0]]);
    }
    const double len = length(n);
    if (!(len > 0)) return false;
    n = n / len;
    const double tol = 1e-6 * cell_;
    for (std::uint32_t t : vtris_[u])
      for (int k = 0; k < 3; ++k)
        if (std::fabs(dot(P_[T_[t][k]] - P_[u], n)) > tol) return false;
    return true;
  }

  // The bound on |f| over a triangle with these corners: 0.9 max_error times the corners'
  // smallest gradient scale.
  double limit_of(const Triangle& t) const { return 0.9 * E_ * std::min({scale_[t[0]], scale_[t[1]], scale_[t[2]]}); }

  // Check (3) below on the moved triangles, with at most `max_n` sample intervals along an edge.
  bool samples_within(int max_n) {
    checks_.clear();
    for (const auto& [t, nt] : moved_) checks_.push_back({nt, limit_of(nt)});
    return triangles_within(max_n);
  }

  // |f| within each listed triangle's limit at its samples: a barycentric grid at most half a
  // cell apart (at most `max_n` intervals along an edge; its corners included) and its centroid.
  // Corners come from the values at the vertices, and an edge two listed triangles share is
  // sampled once, as finely as the finer grid asks and at the stricter limit.
  bool triangles_within(int max_n) {
    xs_.clear(), ys_.clear(), zs_.clear(), limit_.clear(), edges_.clear(), owner_.clear();
    maxima_.assign(checks_.size(), 0.0f);
    auto add = [&](const Vec3& p, double limit, std::int32_t owner) {
      xs_.push_back(static_cast<float>(p.x)), ys_.push_back(static_cast<float>(p.y)), zs_.push_back(static_cast<float>(p.z));
      limit_.push_back(limit);
      owner_.push_back(owner);
    };
    auto intervals = [&](double length) { return std::clamp(static_cast<int>(std::ceil(length / (0.5 * cell_))), 1, max_n); };
    for (std::uint32_t ci = 0; ci < checks_.size(); ++ci) {
      const auto& [nt, limit] = checks_[ci];
      const std::int32_t owner = static_cast<std::int32_t>(ci);
      const Vec3 a = P_[nt[0]], b = P_[nt[1]], c = P_[nt[2]];
      const int n = intervals(std::sqrt(std::max({length2(b - a), length2(c - b), length2(a - c)})));
      for (int k = 0; k < 3; ++k) {
        const float fv = std::fabs(fvertex_[nt[k]]);
        if (!(fv <= limit)) return false;
        maxima_[ci] = std::max(maxima_[ci], fv);
        const std::uint32_t u = nt[k], w = nt[(k + 1) % 3];
        edges_.push_back({std::min(u, w), std::max(u, w), n, limit, ci, 0});
      }
      for (int i = 1; i < n; ++i)
        for (int j = 1; i + j < n; ++j) add(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n), limit, owner);
      add((a + b + c) / 3.0, limit, owner);
    }
    // Each edge once, as finely as its finest triangle's grid and at its strictest limit.
    std::sort(edges_.begin(), edges_.end(),
              [](const EdgeCheck& x, const EdgeCheck& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    std::int32_t groups = 0;
    for (std::size_t e = 0; e < edges_.size(); ++groups) {
      EdgeCheck g = edges_[e];
      edges_[e].group = static_cast<std::uint32_t>(groups);
      for (++e; e < edges_.size() && edges_[e].a == g.a && edges_[e].b == g.b; ++e) {
        g.n = std::max(g.n, edges_[e].n), g.limit = std::min(g.limit, edges_[e].limit);
        edges_[e].group = static_cast<std::uint32_t>(groups);
      }
      const Vec3 a = P_[g.a], b = P_[g.b];
      for (int k = 1; k < g.n; ++k) add(a + (b - a) * (double(k) / g.n), g.limit, -1 - groups);
    }
    if (xs_.empty()) return true;
    out_.resize(xs_.size());
    eval_.eval(tape_, xs_.data(), ys_.data(), zs_.data(), out_.data(), xs_.size());
    edge_max_.assign(static_cast<std::size_t>(groups), 0.0f);
    for (std::size_t i = 0; i < out_.size(); ++i) {
      const float f = std::fabs(out_[i]);
      if (!(f <= limit_[i])) return false;
      const std::int32_t o = owner_[i];
      float& m = o >= 0 ? maxima_[static_cast<std::size_t>(o)] : edge_max_[static_cast<std::size_t>(-1 - o)];
      m = std::max(m, f);
    }
    for (const EdgeCheck& e : edges_) maxima_[e.check] = std::max(maxima_[e.check], edge_max_[e.group]);
    return true;
  }

  // Whether u's triangles (a flat star) are within `limit` at their samples: those not sampled
  // yet, or found above it, are sampled now, and what is found recorded. False if one fails.
  bool star_within(std::uint32_t u, double limit) {
    checks_.clear();
    check_tris_.clear();
    for (std::uint32_t t : vtris_[u])
      if (held_[t] > limit) checks_.push_back({T_[t], limit}), check_tris_.push_back(t);
    if (checks_.empty()) return true;
    if (!triangles_within(64)) return false;
    for (std::size_t c = 0; c < check_tris_.size(); ++c) held_[check_tris_[c]] = maxima_[c];
    return true;
  }

  std::vector<std::uint32_t> nbr_u_, nbr_v_, seen_, check_tris_;
  std::uint32_t qstamp_ = 0;
  std::vector<std::pair<std::uint32_t, Triangle>> moved_;
};

// Regions of the first, parallel round: cubes of this many cells.
constexpr int kRegionCells = 32;

// min(1, |grad f|) at every vertex (Part::scale). E is a distance, the check is on |f|: where a
// field is flatter than a distance (|grad f| < 1; a scaled sphere) triangles could stray
// E / |grad f|. So a triangle's bound on |f| is E times the smallest scale at its corners, by
// central differences a twentieth of a cell wide along the axes (across a crease they
// underestimate it, to about 0.7: the bound only gets stricter). Where that is below 1, the
// largest difference along the four diagonals counts too: at the corner of an axis-aligned box
// the axis probes run along its edges, on the surface, and would give 0, which no collapse at
// the corner could meet (below 0.99: what f32 rounding leaves of a distance field's 1 is not
// worth the probes). (No difference quotient exceeds the field's Lipschitz bound, so a
// distance field's scale stays at most 1 and a flatter field's is not overestimated.)
// Also f at every vertex (into `value`), which every sample check reads at triangles' corners.
std::vector<double> gradient_scales(const std::vector<Vec3>& vs, const Tape& tape, double cell, ThreadPool& pool,
                                    std::vector<float>& value) {
  const double h = 0.05 * cell;
  static const Vec3 kAxes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double d = 1 / std::sqrt(3.0);
  static const Vec3 kDiagonals[4] = {{d, d, d}, {d, d, -d}, {d, -d, d}, {-d, d, d}};
  std::vector<double> scale(vs.size(), 0);
  value.assign(vs.size(), 0.0f);
  struct Scratch {
    BatchEvaluator eval;
    std::vector<float> xs, ys, zs, out;
    std::vector<std::size_t> flat;  // vertices whose axis estimate is below 0.99
  };
  std::vector<Scratch> scratch(static_cast<std::size_t>(pool.size()));
  // f at point(k) for k < n, into out.
  auto eval_at = [&](Scratch& s, std::size_t n, auto&& point, float* out) {
    s.xs.clear(), s.ys.clear(), s.zs.clear();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 q = point(k);
      s.xs.push_back(static_cast<float>(q.x)), s.ys.push_back(static_cast<float>(q.y)), s.zs.push_back(static_cast<float>(q.z));
    }
    s.eval.eval(tape, s.xs.data(), s.ys.data(), s.zs.data(), out, n);
  };
  // Probe k of a vertex: along dirs[k / 2], backwards for even k.
  auto probe = [&](const Vec3& p, const Vec3* dirs, std::size_t k) { return p + dirs[k / 2] * ((k % 2 ? 1.0 : -1.0) * h); };
  pool.parallel_for_ranges(vs.size(), 4096, [&](int worker, std::size_t begin, std::size_t end) {
    Scratch& s = scratch[static_cast<std::size_t>(worker)];
    const std::size_t n = end - begin;
    eval_at(s, n, [&](std::size_t k) { return vs[begin + k]; }, value.data() + begin);
    s.out.resize(6 * n);
    eval_at(s, 6 * n, [&](std::size_t k) { return probe(vs[begin + k / 6], kAxes, k % 6); }, s.out.data());
    s.flat.clear();
    for (std::size_t i = begin; i < end; ++i) {
      const float* f = &s.out[6 * (i - begin)];
      const double gx = (f[1] - f[0]) / (2 * h), gy = (f[3] - f[2]) / (2 * h), gz = (f[5] - f[4]) / (2 * h);
      const double g = std::sqrt(gx * gx + gy * gy + gz * gz);
      scale[i] = std::isfinite(g) ? std::min(1.0, g) : 0;
      if (std::isfinite(g) && g < 0.99) s.flat.push_back(i);
    }
    if (s.flat.empty()) return;
    s.out.resize(8 * s.flat.size());
    eval_at(s, 8 * s.flat.size(), [&](std::size_t k) { return probe(vs[s.flat[k / 8]], kDiagonals, k % 8); }, s.out.data());
    for (std::size_t k = 0; k < s.flat.size(); ++k)
      for (int a = 0; a < 4; ++a) {
        const double g = std::fabs(s.out[8 * k + 2 * a + 1] - s.out[8 * k + 2 * a]) / (2 * h);
        if (std::isfinite(g)) scale[s.flat[k]] = std::min(1.0, std::max(scale[s.flat[k]], g));
      }
  });
  return scale;
}

// Shells (connected components) of the triangles over `n` vertices: per vertex its shell's root
// (the smallest vertex in it), and per root the shell's signed volume, relative to the root.
void shells_of(const std::vector<Vec3>& P, const std::vector<Triangle>& T, std::vector<std::uint32_t>& root,
               std::vector<double>& volume) {
  UnionFind shells(P.size());
  for (const Triangle& tr : T) shells.unite(tr[0], tr[1]), shells.unite(tr[0], tr[2]);
  root = std::move(shells).roots();
  volume.assign(P.size(), 0);
  for (const Triangle& tr : T) {
    const Vec3 o = P[root[tr[0]]];
    volume[root[tr[0]]] += dot(P[tr[0]] - o, cross(P[tr[1]] - o, P[tr[2]] - o)) / 6;
  }
}

// The regions of a round: cubes of kRegionCells cells. A triangle whose corners lie in one region
// is that region's to change; the others (across regions) stay as they are in the round, and
// their corners are frozen.
struct Regions {
  double size = 0;
  Vec3 origin;
  std::vector<std::uint64_t> keys;          // the regions with vertices, sorted
  std::vector<std::uint32_t> of_vertex;     // per vertex: its region (index into keys)
  std::vector<std::vector<std::uint32_t>> inside;  // per region: its triangles
  std::vector<std::vector<std::uint32_t>> around;  // per region: triangles across regions near it
  std::vector<std::uint32_t> across;        // triangles across regions
  std::vector<char> frozen;                 // per vertex: a corner of a triangle across regions

  // Region coordinate of x along axis a (monotone in x, so regions along an axis never interleave).
  std::int64_t coord(double x, int a) const {
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((x - origin[a]) / size)), 0, (1 << 20) - 1);
  }
  std::int64_t find(std::uint64_t k) const {
    const auto it = std::lower_bound(keys.begin(), keys.end(), k);
    return it != keys.end() && *it == k ? it - keys.begin() : -1;
  }

  // Regions moved by `shift` of a region from the mesh's low corner.
  Regions(const std::vector<Vec3>& P, const std::vector<Triangle>& T, double cell, double shift) {
    size = kRegionCells * cell;
    Box3 bb;
    for (const Vec3& p : P) bb.add(p);
    origin = bb.lo - Vec3{1, 1, 1} * (shift * size);
    std::vector<std::uint64_t> vkey(P.size());
    for (std::size_t v = 0; v < P.size(); ++v) {
      const Vec3& p = P[v];
      vkey[v] = cell_key(coord(p.x, 0), coord(p.y, 1), coord(p.z, 2));
    }
    keys = vkey;
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    of_vertex.resize(P.size());
    for (std::size_t v = 0; v < P.size(); ++v) of_vertex[v] = static_cast<std::uint32_t>(find(vkey[v]));
    inside.resize(keys.size());
    around.resize(keys.size());
    frozen.assign(P.size(), 0);
    for (std::uint32_t t = 0; t < T.size(); ++t) {
      const Triangle& tr = T[t];
      const std::uint32_t r = of_vertex[tr[0]];
      if (of_vertex[tr[1]] == r && of_vertex[tr[2]] == r) {
        inside[r].push_back(t);
        continue;
      }
      across.push_back(t);
      for (std::uint32_t v : tr) frozen[v] = 1;
      // Every region whose box the triangle's box meets (one region of margin for rounding):
      // what a region changes stays inside its own box, so these are all it can run into.
      Box3 tb;
      for (std::uint32_t v : tr) tb.add(P[v]);
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) lo[a] = coord(tb.lo[a], a) - 1, hi[a] = coord(tb.hi[a], a) + 1;
      for (std::int64_t i = std::max<std::int64_t>(lo[0], 0); i <= hi[0]; ++i)
        for (std::int64_t j = std::max<std::int64_t>(lo[1], 0); j <= hi[1]; ++j)
          for (std::int64_t k = std::max<std::int64_t>(lo[2], 0); k <= hi[2]; ++k)
            if (const std::int64_t r2 = find(cell_key(i, j, k)); r2 >= 0) around[static_cast<std::size_t>(r2)].push_back(t);
    }
  }
  // Region r's box, with `margin` around it.
  Box3 box(std::size_t r, double margin) const {
    const std::uint64_t k = keys[r];
    const double c[3] = {static_cast<double>(k >> 42), static_cast<double>(k >> 21 & 0x1fffff), static_cast<double>(k & 0x1fffff)};
    Box3 b;
    for (int a = 0; a < 3; ++a) b.lo[a] = origin[a] + c[a] * size - margin, b.hi[a] = origin[a] + (c[a] + 1) * size + margin;
    return b;
  }
};

// The triangles and per-vertex state the rounds pass on.
struct Stage {
  std::vector<Triangle> T;
  std::vector<Quadric> Q;
  std::vector<char> seed;  // vertices whose edges are to be tried; empty: all
};

// One round in parallel over regions moved by `shift` of a region: each region is simplified on
// its own with the field's tape pruned to it; triangles across regions and their corners stay as
// they are, and a shell that spans regions may change its volume in each by at most its share of
// half of it. Leaves in `st.seed` the vertices with collapses left to try.
// `done(r, n)` is called after each of the n regions (r of them done), one call at a time.
void region_round(const std::vector<Vec3>& P, Stage& st, const std::vector<double>& scale,
                  const std::vector<float>& value, double shift,
                  const Tape& tape, double E, double cell, ThreadPool& pool, SimplifyReport& rep,
                  const std::function<void(std::size_t, std::size_t)>& done) {
  const std::size_t nv = P.size();
  const std::vector<Triangle> T = std::move(st.T);
  std::vector<std::uint32_t> root;
  std::vector<double> volume;
  shells_of(P, T, root, volume);
  const Regions regions(P, T, cell, shift);
  const std::size_t nr = regions.keys.size();
  // Per shell (at its root): how many regions it has vertices in.
  std::vector<std::uint32_t> spans(nv, 0);
  {
    std::vector<std::uint64_t> pairs(nv);
    for (std::size_t v = 0; v < nv; ++v) pairs[v] = static_cast<std::uint64_t>(root[v]) << 32 | regions.of_vertex[v];
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const std::uint64_t p : pairs) ++spans[p >> 32];
  }
  std::vector<std::vector<Triangle>> kept(nr);
  std::vector<char> pending(nv, 0);
  std::vector<SimplifyReport> reps(nr);
  struct Scratch {
    std::vector<std::uint32_t> local;  // per vertex of the mesh: its index in the part, or ~0
    IntervalEvaluator intervals;
  };
  std::vector<Scratch> scratch(static_cast<std::size_t>(pool.size()));
  for (Scratch& s : scratch) s.local.assign(nv, ~0u);
  std::mutex mutex;
  std::size_t finished = 0;
  pool.parallel_for(static_cast<int>(nr), [&](int worker, int item) {
    const std::size_t r = static_cast<std::size_t>(item);
    Scratch& s = scratch[static_cast<std::size_t>(worker)];
    Part part;
    std::vector<std::uint32_t> global;
    std::vector<std::uint32_t> shells;  // roots of the part's shells
    auto local = [&](std::uint32_t g) {
      if (s.local[g] == ~0u) {
        s.local[g] = static_cast<std::uint32_t>(global.size());
        global.push_back(g);
      }
      return s.local[g];
    };
    for (const auto* list : {&regions.inside[r], &regions.around[r]})
      for (std::uint32_t t : *list) {
        const Triangle& tr = T[t];
        part.T.push_back({local(tr[0]), local(tr[1]), local(tr[2])});
      }
    for (std::uint32_t g : global) {
      part.P.push_back(P[g]);
      part.scale.push_back(scale[g]);
      part.value.push_back(value[g]);
      part.Q.push_back(st.Q[g]);
      part.frozen.push_back(regions.frozen[g] || regions.of_vertex[g] != r);
      if (!st.seed.empty()) part.seed.push_back(st.seed[g]);
      shells.push_back(root[g]);
    }
    std::sort(shells.begin(), shells.end());
    shells.erase(std::unique(shells.begin(), shells.end()), shells.end());
    for (std::uint32_t g : global)
      part.shell.push_back(static_cast<std::uint32_t>(std::lower_bound(shells.begin(), shells.end(), root[g]) - shells.begin()));
    for (std::uint32_t sh : shells) {
      part.volume.push_back(volume[sh]);
      part.budget.push_back(spans[sh] > 1 ? std::fabs(volume[sh]) / (2.0 * spans[sh]) : INFINITY);
    }
    // The field pruned to the region (a cell of margin: samples are rounded to f32).
    const Box3 b = regions.box(r, cell);
    Tape pruned;
    s.intervals.simplify(tape, Interval{static_cast<float>(b.lo.x), static_cast<float>(b.hi.x)},
                         Interval{static_cast<float>(b.lo.y), static_cast<float>(b.hi.y)},
                         Interval{static_cast<float>(b.lo.z), static_cast<float>(b.hi.z)}, pruned);
    const std::size_t n_inside = regions.inside[r].size();
    Simplifier simp(std::move(part), pruned, E, cell);
    simp.run(reps[r]);
    for (std::uint32_t t = 0; t < n_inside; ++t)
      if (simp.alive(t)) {
        const Triangle& tr = simp.triangles()[t];
        kept[r].push_back({global[tr[0]], global[tr[1]], global[tr[2]]});
      }
    // Each vertex is written by its own region only (others have it frozen, where nothing
    // changes but a pending flag, which the region that owns it sets as well).
    for (std::uint32_t l = 0; l < global.size(); ++l) {
      const std::uint32_t g = global[l];
      if (regions.of_vertex[g] == r) {
        st.Q[g] = simp.quadric(l);
        pending[g] = simp.pending(l);
      }
      s.local[g] = ~0u;
    }
    std::lock_guard<std::mutex> lock(mutex);
    done(++finished, nr);
  });
  for (const SimplifyReport& r : reps) rep.collapses += r.collapses, rep.rejected += r.rejected;
  st.T.clear();
  for (const auto& k : kept) st.T.insert(st.T.end(), k.begin(), k.end());
  for (std::uint32_t t : regions.across) st.T.push_back(T[t]);
  st.seed = std::move(pending);
}

}  // namespace

// Two rounds over regions (cubes of kRegionCells cells) in parallel, the second moved by half a
// region so that it works across the first one's seams; then the whole mesh on one thread, from
// the vertices the region rounds left collapses to try. The regions do not depend on the thread
// count, so neither does the result.
TriMesh simplify_mesh(const TriMesh& mesh, const Tape& tape, const SimplifyOptions& options, SimplifyReport* report) {
  SimplifyReport rep;
  const double E = options.max_error, cell = options.cell_size;
  const std::size_t nv = mesh.vertices.size();
  ThreadPool pool(resolve_thread_count(options.threads));
  std::vector<float> value;
  const std::vector<double> scale = gradient_scales(mesh.vertices, tape, cell, pool, value);
  Stage st;
  st.T = mesh.triangles;
  st.Q.resize(nv);
  for (const Triangle& tr : mesh.triangles) {
    const Vec3 n2 = cross(mesh.vertices[tr[1]] - mesh.vertices[tr[0]], mesh.vertices[tr[2]] - mesh.vertices[tr[0]]);
    const double len = length(n2);
    if (!(len > 0)) continue;
    const Vec3 n = n2 / len;
    for (std::uint32_t v : tr) st.Q[v].add_plane(n, -dot(n, mesh.vertices[tr[0]]), 0.5 * len);
  }
  // Progress: the first round is most of the work, the last pass a little.
  const double share[2] = {0.75, 0.2};
  for (int round = 0; round < 2; ++round)
    region_round(mesh.vertices, st, scale, value, round * 0.5, tape, E, cell, pool, rep, [&](std::size_t r, std::size_t n) {
      if (options.cancelled && options.cancelled()) throw MeshCancelled();
      if (options.progress) options.progress((round ? share[0] : 0) + share[round] * static_cast<double>(r) / n);
    });
  if (std::any_of(st.seed.begin(), st.seed.end(), [](char c) { return c != 0; })) {
    Part whole;
    whole.P = mesh.vertices;
    whole.T = std::move(st.T);
    whole.scale = scale;
    whole.value = std::move(value);
    whole.Q = std::move(st.Q);
    shells_of(whole.P, whole.T, whole.shell, whole.volume);
    whole.budget.assign(nv, INFINITY);
    whole.frozen.assign(nv, 0);
    whole.seed = std::move(st.seed);
    Simplifier simp(std::move(whole), tape, E, cell);
    simp.run(rep);
    st.T.clear();
    for (std::uint32_t t = 0; t < simp.triangles().size(); ++t)
      if (simp.alive(t)) st.T.push_back(simp.triangles()[t]);
  }
  if (options.progress) options.progress(1);
  if (report) *report = rep;
  return compact_mesh(mesh.vertices, st.T);
}

}  // namespace frep::contour
