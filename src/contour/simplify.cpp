// Error-bounded simplification (simplify.hpp): Garland-Heckbert quadrics order half-edge
// collapses in a lazy priority queue; a collapse is applied only if four checks all hold.
#include "contour/simplify.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <vector>

#include "frep/eval/evaluators.hpp"
#include "frep/mesh/tri_tri.hpp"
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

// 4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle, 0 for a flat one.
double quality(const Vec3& p, const Vec3& q, const Vec3& r) {
  const double e = length2(q - p) + length2(r - q) + length2(p - r);
  return e > 0 ? 2 * std::sqrt(3.0) * length(cross(q - p, r - p)) / e : 0;
}

class Simplifier {
 public:
  Simplifier(const TriMesh& m, const Tape& tape, const SimplifyOptions& o)
      : P_(m.vertices), T_(m.triangles), tape_(tape), E_(o.max_error), cell_(o.cell_size) {
    alive_.assign(T_.size(), 1);
    vdead_.assign(P_.size(), 0);
    vtris_.resize(P_.size());
    Q_.resize(P_.size());
    version_.assign(P_.size(), 0);
    mark_.assign(T_.size(), 0);
    held_.assign(T_.size(), INFINITY);
    hash_size_ = 4 * cell_;
    E_ = o.max_error;
    gradient_scales(m.vertices);
    for (std::uint32_t t = 0; t < T_.size(); ++t) {
      const Triangle& tr = T_[t];
      for (int k = 0; k < 3; ++k) vtris_[tr[k]].push_back(t);
      const Vec3 n2 = cross(P_[tr[1]] - P_[tr[0]], P_[tr[2]] - P_[tr[0]]);
      const double len = length(n2);
      if (len > 0) {
        const Vec3 n = n2 / len;
        for (int k = 0; k < 3; ++k) Q_[tr[k]].add_plane(n, -dot(n, P_[tr[0]]), 0.5 * len);
      }
      hash_insert(t);
    }
    // Shells (connected components) and their signed volumes, relative to each shell's first
    // vertex: a collapse never turns a shell inside out, which a tiny cavity (a tetrahedron of
    // volume 1e-12) would otherwise undergo while each of its triangles turns less than the
    // flip check allows.
    UnionFind shells(P_.size());
    for (const Triangle& tr : T_) shells.unite(tr[0], tr[1]), shells.unite(tr[0], tr[2]);
    shell_ = std::move(shells).roots();
    volume_.assign(P_.size(), 0);
    for (const Triangle& tr : T_) {
      const Vec3 o = P_[shell_[tr[0]]];
      volume_[shell_[tr[0]]] += dot(P_[tr[0]] - o, cross(P_[tr[1]] - o, P_[tr[2]] - o)) / 6;
    }
    for (std::uint32_t t = 0; t < T_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = T_[t][k], b = T_[t][(k + 1) % 3];
        if (a < b) push(a, b), push(b, a);  // each edge once (the other triangle has b -> a)
      }
  }

  TriMesh run(SimplifyReport& rep) {
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
    return compact();
  }

 private:
  std::vector<Vec3> P_;
  std::vector<Triangle> T_;
  const Tape& tape_;
  double E_, cell_, hash_size_;
  std::vector<char> alive_, vdead_;
  std::vector<double> scale_;  // per vertex: min(1, |grad f|), which scales E into a bound on |f|
  std::vector<std::vector<std::uint32_t>> vtris_;
  std::vector<Quadric> Q_;
  std::vector<std::uint32_t> version_, mark_;
  std::vector<std::uint32_t> shell_;  // per vertex: its shell (the smallest vertex index in it)
  std::vector<double> volume_;        // per shell (at its index): signed volume
  std::vector<double> held_;          // per triangle: the bound on |f| its samples were checked to hold (infinite: never checked)
  std::vector<std::pair<Triangle, double>> checks_;  // triangles to sample, with their limits
  std::uint32_t stamp_ = 0;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap_;
  // Spatial hash: per cell, entries (triangle << 32 | its version when inserted). A triangle that
  // moves gets a new version and new entries; old ones are dropped when their cell is next read.
  std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> hash_;
  std::vector<std::uint32_t> tver_;  // per triangle: its version
  BatchEvaluator eval_;
  std::vector<float> xs_, ys_, zs_, out_;
  std::vector<double> limit_;  // per sample: the bound on |f| of its triangle

  // E is a distance, the check is on |f|: where a field is flatter than a distance (|grad f| < 1;
  // a scaled sphere) triangles could stray E / |grad f|. So a triangle's bound on |f| is E times
  // the smallest min(1, |grad f|) at its corners, by central differences a twentieth of a cell
  // wide (across a crease they underestimate it, to about 0.7: the bound only gets stricter).
  void gradient_scales(const std::vector<Vec3>& vs) {
    const double h = 0.05 * cell_;
    xs_.clear(), ys_.clear(), zs_.clear();
    for (const Vec3& p : vs)
      for (int a = 0; a < 3; ++a)
        for (double sgn : {-1.0, 1.0}) {
          Vec3 q = p;
          q[a] += sgn * h;
          xs_.push_back(static_cast<float>(q.x)), ys_.push_back(static_cast<float>(q.y)), zs_.push_back(static_cast<float>(q.z));
        }
    out_.resize(xs_.size());
    eval_.eval(tape_, xs_.data(), ys_.data(), zs_.data(), out_.data(), xs_.size());
    scale_.assign(vs.size(), 0);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const float* f = &out_[6 * i];
      const double gx = (f[1] - f[0]) / (2 * h), gy = (f[3] - f[2]) / (2 * h), gz = (f[5] - f[4]) / (2 * h);
      const double g = std::sqrt(gx * gx + gy * gy + gz * gz);
      scale_[i] = std::isfinite(g) ? std::min(1.0, g) : 0;
    }
  }

  void push(std::uint32_t u, std::uint32_t v) {
    Quadric q = Q_[u];
    q.add(Q_[v]);
    heap_.push({std::max(0.0, q.at(P_[v])), length2(P_[u] - P_[v]), u, v, version_[v]});
  }

  std::array<std::int64_t, 3> hash_cell(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x / hash_size_)), static_cast<std::int64_t>(std::floor(p.y / hash_size_)),
            static_cast<std::int64_t>(std::floor(p.z / hash_size_))};
  }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    return (static_cast<std::uint64_t>(i & 0x1fffff) << 42) | (static_cast<std::uint64_t>(j & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(k & 0x1fffff);
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
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k) f(key(i, j, k));
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
    const double before = volume_[shell_[v]], after = before + change;
    if (!(after != 0) || (after > 0) != (before > 0)) return false;

    // A few samples first (corners, edge midpoints, centroid): most refusals are found there,
    // before the costlier crossing test and the full grid of samples.
    // A flat star (u's triangles in one plane, as on the faces of CAD parts) is re-triangulated
    // in place: without flips the new triangles cover exactly the old ones' points, which were
    // within the bound already, so the field needs no samples there.
    double star_limit = INFINITY;  // the strictest limit of the new triangles
    for (const auto& [t, nt] : moved_) star_limit = std::min(star_limit, limit_of(nt));
    const bool flat = star_is_flat(u) && star_within(u, star_limit);
    if (!flat && !samples_within(2)) return false;

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
    // What the new triangles are known to hold: their own limit where they were sampled, the
    // star's where they re-triangulate a flat star whose triangles held it.
    for (const auto& [t, nt] : moved_) {
      held_[t] = flat ? star_limit : limit_of(nt);
      T_[t] = nt;
      vtris_[v].push_back(t);
      hash_insert(t);
    }
    vtris_[u].clear();
    vtris_[u].shrink_to_fit();
    vdead_[u] = 1;
    Q_[v].add(Q_[u]);
    volume_[shell_[v]] = after;
    ++version_[v];
    ring(v, nbr_v_);
    for (std::uint32_t w : nbr_v_)
      if (w != v) push(w, v), push(v, w);
    return true;
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

  // |f| within each listed triangle's limit at its samples (a barycentric grid at most half a
  // cell apart, at most `max_n` intervals along an edge, and the centroid).
  bool triangles_within(int max_n) {
    xs_.clear(), ys_.clear(), zs_.clear(), limit_.clear();
    for (const auto& [nt, limit] : checks_) {
      const Vec3 a = P_[nt[0]], b = P_[nt[1]], c = P_[nt[2]];
      const double longest = std::sqrt(std::max({length2(b - a), length2(c - b), length2(a - c)}));
      const int n = std::clamp(static_cast<int>(std::ceil(longest / (0.5 * cell_))), 1, max_n);
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const double wb = double(i) / n, wc = double(j) / n;
          const Vec3 p = a + (b - a) * wb + (c - a) * wc;
          xs_.push_back(static_cast<float>(p.x)), ys_.push_back(static_cast<float>(p.y)), zs_.push_back(static_cast<float>(p.z));
        }
      const Vec3 g = (a + b + c) / 3.0;
      xs_.push_back(static_cast<float>(g.x)), ys_.push_back(static_cast<float>(g.y)), zs_.push_back(static_cast<float>(g.z));
      limit_.resize(xs_.size(), limit);
    }
    out_.resize(xs_.size());
    eval_.eval(tape_, xs_.data(), ys_.data(), zs_.data(), out_.data(), xs_.size());
    for (std::size_t i = 0; i < out_.size(); ++i)
      if (!(std::fabs(out_[i]) <= limit_[i])) return false;
    return true;
  }

  // A flat star whose triangles all hold a bound no looser than `limit`: checks (at their
  // samples) those that do not yet, and records it. False if one fails.
  bool star_within(std::uint32_t u, double limit) {
    checks_.clear();
    for (std::uint32_t t : vtris_[u])
      if (held_[t] > limit) checks_.push_back({T_[t], limit});
    if (checks_.empty()) return true;
    if (!triangles_within(64)) return false;
    for (std::uint32_t t : vtris_[u]) held_[t] = std::min(held_[t], limit);
    return true;
  }

  TriMesh compact() const {
    TriMesh out;
    std::vector<std::uint32_t> id(P_.size(), 0xffffffffu);
    std::vector<char> used(P_.size(), 0);
    for (std::uint32_t t = 0; t < T_.size(); ++t)
      if (alive_[t])
        for (int k = 0; k < 3; ++k) used[T_[t][k]] = 1;
    for (std::uint32_t i = 0; i < P_.size(); ++i)
      if (used[i]) {
        id[i] = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(P_[i]);
      }
    for (std::uint32_t t = 0; t < T_.size(); ++t)
      if (alive_[t]) out.add_triangle(id[T_[t][0]], id[T_[t][1]], id[T_[t][2]]);
    return out;
  }

  std::vector<std::uint32_t> nbr_u_, nbr_v_, seen_;
  std::uint32_t qstamp_ = 0;
  std::vector<std::pair<std::uint32_t, Triangle>> moved_;
};

}  // namespace

TriMesh simplify_mesh(const TriMesh& mesh, const Tape& tape, const SimplifyOptions& options, SimplifyReport* report) {
  SimplifyReport rep;
  Simplifier s(mesh, tape, options);
  TriMesh out = s.run(rep);
  if (report) *report = rep;
  return out;
}

}  // namespace frep::contour
