// compare_meshes (mesh_pair.hpp): both meshes are placed in the common frame and scaled by one
// power of two, each gets the project's hierarchy (TriangleBvh) over its placed triangles, whose
// outward rounded float boxes prune without deciding anything; then one dual traversal lists the
// triangle pairs whose boxes meet and classifies them exactly, and, when no pair meets, a second
// dual traversal finds the closest pair of triangles, discarding node pairs whose boxes (and
// leaf and triangle pairs whose projections onto the line between them) are farther apart than
// the best distance found so far.
#include "frep/mesh/mesh_pair.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <utility>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep {
namespace {

// --- Triangle-triangle distance pieces (double precision).

// Closest point to p on segment ab (a point if a == b).
inline Vec3 on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = dot(ab, ab);
  if (!(l2 > 0)) return a;
  return a + ab * std::clamp(dot(p - a, ab) / l2, 0.0, 1.0);
}

struct Candidate {
  double d2 = std::numeric_limits<double>::infinity();
  Vec3 p, q;
  void offer(const Vec3& a, const Vec3& b) {
    const double e = length2(a - b);
    if (e < d2) d2 = e, p = a, q = b;
  }
};

// The interior case of two segments: where the common perpendicular of their lines meets both
// inside. Parameters from cross products (|d1 x d2|^2 has no cancellation, unlike a e - b^2), so
// nearly parallel segments keep accurate parameters; exactly parallel ones have no interior case
// (their closest points include an endpoint, which the endpoint cases cover).
inline void segment_interiors(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Candidate& c) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, n = cross(d1, d2);
  const double n2 = length2(n);
  if (!(n2 > 0)) return;
  const Vec3 r = q0 - p0;
  const double s = dot(cross(r, d2), n) / n2, t = dot(cross(r, d1), n) / n2;
  if (!(s > 0 && s < 1 && t > 0 && t < 1)) return;
  c.offer(p0 + d1 * s, q0 + d2 * t);
}

// The vertex-face case: p's projection onto triangle q's plane, if it falls inside q.
inline void vertex_face(const Vec3& p, const Vec3 q[3], const Vec3& n, double n2, bool p_first, Candidate& c) {
  if (!(n2 > 0)) return;
  for (int k = 0; k < 3; ++k)
    if (dot(cross(q[(k + 1) % 3] - q[k], p - q[k]), n) < 0) return;
  const Vec3 foot = p - n * (dot(p - q[0], n) / n2);
  if (p_first) c.offer(p, foot);
  else c.offer(foot, p);
}

// Distance from a point to a triangle (for choosing a contact point only).
double point_triangle2(const Vec3& x, const Vec3 q[3]) {
  Candidate c;
  const Vec3 n = cross(q[1] - q[0], q[2] - q[0]);
  vertex_face(x, q, n, length2(n), true, c);
  for (int k = 0; k < 3; ++k) c.offer(x, on_segment(x, q[k], q[(k + 1) % 3]));
  return c.d2;
}

// A point where two meeting triangles meet: for crossing ones, the edge-plane crossing that lies
// nearest the other triangle; otherwise (touching) their closest points.
Vec3 contact_point(const Vec3 p[3], const Vec3 q[3]) {
  Vec3 a, b;
  double best = triangle_distance2(p, q, a, b);
  Vec3 point = (a + b) * 0.5;
  for (int side = 0; side < 2; ++side) {
    const Vec3* e = side == 0 ? p : q;
    const Vec3* f = side == 0 ? q : p;
    const Vec3 n = cross(f[1] - f[0], f[2] - f[0]);
    for (int k = 0; k < 3; ++k) {
      const Vec3 &e0 = e[k], &e1 = e[(k + 1) % 3];
      const double s0 = dot(e0 - f[0], n), s1 = dot(e1 - f[0], n);
      if (!((s0 < 0 && s1 > 0) || (s0 > 0 && s1 < 0))) continue;
      const Vec3 x = e0 + (e1 - e0) * (s0 / (s0 - s1));
      const double d2 = point_triangle2(x, f);
      if (d2 < best) best = d2, point = x;
    }
  }
  return point;
}

// --- One mesh, placed and indexed.

using Node = TriangleBvh::Node;

// Leaves of up to 16 triangles: a leaf pair is first measured as a whole by projecting its
// corners (DistanceSearch::projected_gap), which is much tighter than boxes where surfaces are
// nearly equidistant over a wide area; smaller leaves leave more of that to boxes (two nearly
// concentric spheres of 200,000 triangles, 1 apart: 0.8 s with 16, 2.1 s with 4).
constexpr int kLeafSize = 16;

// The project's hierarchy over the placed triangles (its float boxes, rounded outward, contain
// the double triangles: pruning by them never loses a pair), and the triangles' corners in its
// leaf order, which is how the traversals read them.
struct Side {
  const MeshField* field = nullptr;
  TriMesh placed;                         // welded triangles, placed and scaled vertices
  TriangleBvh bvh;                        // over `placed`
  std::vector<std::array<Vec3, 3>> tri;   // corners, leaf order
  std::vector<Vec3> centre;               // centroids, leaf order
  std::vector<std::uint8_t> usable;       // leaf order: spans a plane (collinear corners do not)

  const std::vector<Node>& nodes() const { return bvh.nodes(); }
  std::uint32_t id(std::uint32_t i) const { return bvh.order()[i]; }  // leaf order -> triangle index

  void index() {
    BvhOptions bo;
    bo.max_leaf_size = kLeafSize;
    bvh = TriangleBvh(placed, bo);
    const std::size_t n = placed.triangles.size();
    tri.resize(n);
    centre.resize(n);
    usable.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Triangle& v = placed.triangles[id(static_cast<std::uint32_t>(i))];
      for (int k = 0; k < 3; ++k) tri[i][k] = placed.vertices[v[k]];
      centre[i] = (tri[i][0] + tri[i][1] + tri[i][2]) / 3.0;
      // Collapsed or collinear triangles are skipped by the contact test (it needs a plane);
      // their edges belong to their neighbours too. Exact: all three projections are collinear.
      const auto& c = tri[i];
      const bool distinct = v[0] != v[1] && v[1] != v[2] && v[0] != v[2];
      usable[i] = distinct && (exact::orient2d(c[0].x, c[0].y, c[1].x, c[1].y, c[2].x, c[2].y) != 0 ||
                               exact::orient2d(c[0].y, c[0].z, c[1].y, c[1].z, c[2].y, c[2].z) != 0 ||
                               exact::orient2d(c[0].z, c[0].x, c[1].z, c[1].x, c[2].z, c[2].x) != 0);
    }
  }
};

// Squared distance between two boxes (a lower bound of any distance between their contents, up
// to the rounding the pruning margin allows for).
double gap2(const float* alo, const float* ahi, const float* blo, const float* bhi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max({0.0, double(blo[k]) - double(ahi[k]), double(alo[k]) - double(bhi[k])});
    s += g * g;
  }
  return s;
}
double node_gap2(const Node& a, const Node& b) { return gap2(a.lo, a.hi, b.lo, b.hi); }
double triangle_gap2(const Side& A, std::uint32_t i, const Side& B, std::uint32_t j) {
  const float *a = A.bvh.triangle_box(i), *b = B.bvh.triangle_box(j);
  return gap2(a, a + 3, b, b + 3);
}

struct NodePair {
  std::uint32_t a, b;
};

// Node pairs near the roots, expanded breadth-first until there are about `want` of them (pairs
// that `keep` rejects are dropped), in a fixed order: the independent jobs of a parallel traversal.
template <class Keep>
std::vector<NodePair> top_pairs(const Side& A, const Side& B, std::size_t want, Keep keep) {
  std::vector<NodePair> jobs;
  if (keep(A.nodes()[0], B.nodes()[0])) jobs.push_back({0, 0});
  for (int round = 0; round < 16 && !jobs.empty() && jobs.size() < want; ++round) {
    std::vector<NodePair> next;
    bool opened = false;
    for (const NodePair& j : jobs) {
      const Node &na = A.nodes()[j.a], &nb = B.nodes()[j.b];
      if (na.leaf() && nb.leaf()) {
        next.push_back(j);
        continue;
      }
      opened = true;
      const bool oa = TriangleBvh::open_first(na, nb);
      for (std::uint32_t c = 0; c < 2; ++c) {
        const NodePair k = oa ? NodePair{na.index + c, j.b} : NodePair{j.a, nb.index + c};
        if (keep(A.nodes()[k.a], B.nodes()[k.b])) next.push_back(k);
      }
    }
    jobs.swap(next);
    if (!opened) break;
  }
  return jobs;
}

// --- Contacts.

struct Tally {
  std::size_t count[3] = {0, 0, 0};                       // by PairContact
  std::priority_queue<std::uint64_t> first[3];            // the smallest (a << 32 | b) seen, as a max-heap
  std::size_t keep = 0;
  void add(int kind, std::uint32_t a, std::uint32_t b) {
    ++count[kind];
    if (keep == 0) return;
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    auto& h = first[kind];
    if (h.size() < keep) h.push(key);
    else if (key < h.top()) h.pop(), h.push(key);
  }
};

// Classifies every pair of usable triangles below a node pair whose (outward rounded) boxes
// overlap: a superset of the pairs that meet, each decided exactly.
void contacts_below(const Side& A, const Side& B, NodePair start, Tally& tally) {
  A.bvh.for_each_overlapping_pair_below(start.a, B.bvh, start.b, [&](std::uint32_t i, std::uint32_t j) {
    if (!A.usable[i] || !B.usable[j]) return;
    // Different meshes share no vertex: distinct indices make every coincidence a contact.
    static constexpr unsigned pi[3] = {0, 1, 2}, qi[3] = {3, 4, 5};
    const Contact c = classify_triangle_pair(A.tri[i].data(), pi, B.tri[j].data(), qi);
    if (c == Contact::Cross) tally.add(int(PairContact::Cross), A.id(i), B.id(j));
    else if (c == Contact::Overlap) tally.add(int(PairContact::Overlap), A.id(i), B.id(j));
    else if (c == Contact::Touch) tally.add(int(PairContact::Touch), A.id(i), B.id(j));
  });
}

// --- Distance.

// The best pair so far: ordered by squared distance, then by triangle indices, so that the
// answer does not depend on which thread found what first.
struct Best {
  double d2 = std::numeric_limits<double>::infinity();
  std::uint32_t a = 0xffffffffu, b = 0xffffffffu;
  Vec3 pa, pb;
  bool better(double e2, std::uint32_t ta, std::uint32_t tb) const {
    if (e2 != d2) return e2 < d2;
    return ta != a ? ta < a : tb < b;
  }
};

// Distances here are in the scaled frame (coordinates below 1 in magnitude), where the rounding
// of a computed distance or box gap is far below this: a node pair is discarded only when its
// box gap exceeds the best distance by more, so every pair that could be the (rounded) minimum
// is examined whatever the order, and the result is the same for any number of threads.
constexpr double kMargin = 1e-12;

class DistanceSearch {
 public:
  DistanceSearch(const Side& A, const Side& B) : A_(A), B_(B) {}

  // The best squared distance found by any thread, and the squared gap beyond which a pair is
  // discarded, (sqrt(best) + kMargin)^2: both only decrease, each by its own compare-exchange.
  std::atomic<double> bound2{std::numeric_limits<double>::infinity()};
  std::atomic<double> prune2{std::numeric_limits<double>::infinity()};

  bool far(double gap2_value) const { return gap2_value > prune2.load(std::memory_order_relaxed); }

  void lower_bound_to(double d2) {
    const auto lower = [](std::atomic<double>& a, double v) {
      double cur = a.load(std::memory_order_relaxed);
      while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
      }
    };
    if (!(d2 < bound2.load(std::memory_order_relaxed))) return;
    lower(bound2, d2);
    const double b = std::sqrt(d2) + kMargin;
    lower(prune2, b * b);
  }

  // The gap between two point sets' projections onto the line from one centre to the other (a
  // lower bound of their distance: projecting onto a unit vector shortens no distance), or 0.
  // Boxes are loose by about their size; this, for small sets far apart, by its square over the
  // distance, which matters where many pairs are nearly as close as the closest (nearly
  // concentric curved surfaces).
  template <class PointsA, class PointsB>
  static double projected_gap(const Vec3& ca, const Vec3& cb, PointsA pa, PointsB pb) {
    const Vec3 axis = cb - ca;
    const double l2 = length2(axis);
    if (!(l2 > 0)) return 0;
    const Vec3 u = axis / std::sqrt(l2);
    double hi_a = -std::numeric_limits<double>::infinity(), lo_b = std::numeric_limits<double>::infinity();
    pa([&](const Vec3& v) { hi_a = std::max(hi_a, dot(v, u)); });
    pb([&](const Vec3& v) { lo_b = std::min(lo_b, dot(v, u)); });
    return std::max(0.0, lo_b - hi_a);
  }

  void leaves(const Node& na, const Node& nb, Best& best) {
    // The two leaves as wholes first.
    const auto mid = [](const Node& n) {
      return Vec3{(double(n.lo[0]) + n.hi[0]) / 2, (double(n.lo[1]) + n.hi[1]) / 2, (double(n.lo[2]) + n.hi[2]) / 2};
    };
    const Vec3 ca = mid(na), cb = mid(nb);
    const auto corners = [](const Side& s, const Node& n) {
      return [&s, &n](auto f) {
        for (std::uint32_t i = n.index; i < n.index + n.count; ++i)
          for (const Vec3& v : s.tri[i]) f(v);
      };
    };
    const double leaf_gap = projected_gap(ca, cb, corners(A_, na), corners(B_, nb));
    if (far(leaf_gap * leaf_gap)) return;
    for (std::uint32_t i = na.index; i < na.index + na.count; ++i)
      for (std::uint32_t j = nb.index; j < nb.index + nb.count; ++j) {
        if (far(triangle_gap2(A_, i, B_, j))) continue;
        const auto& p = A_.tri[i];
        const auto& q = B_.tri[j];
        const double gap = projected_gap(A_.centre[i], B_.centre[j], [&](auto f) { for (const Vec3& v : p) f(v); },
                                         [&](auto f) { for (const Vec3& v : q) f(v); });
        if (far(gap * gap)) continue;
        Vec3 x, y;
        const double d2 = triangle_distance2(p.data(), q.data(), x, y);
        if (best.better(d2, A_.id(i), B_.id(j))) best = {d2, A_.id(i), B_.id(j), x, y};
        lower_bound_to(d2);
      }
  }

  // Depth first from `start`, the nearer child pair first. Entries carry their box gap, so that
  // a pair is measured once and checked again, against the bound of the moment, when taken.
  void below(NodePair start, Best& best) {
    struct Entry {
      NodePair pair;
      double gap2;
    };
    const auto& an = A_.nodes();
    const auto& bn = B_.nodes();
    std::vector<Entry> stack{{start, node_gap2(an[start.a], bn[start.b])}};
    while (!stack.empty()) {
      const Entry e = stack.back();
      stack.pop_back();
      if (far(e.gap2)) continue;
      const Node &na = an[e.pair.a], &nb = bn[e.pair.b];
      if (na.leaf() && nb.leaf()) {
        leaves(na, nb, best);
        continue;
      }
      NodePair c0, c1;
      if (TriangleBvh::open_first(na, nb)) c0 = {na.index, e.pair.b}, c1 = {na.index + 1, e.pair.b};
      else c0 = {e.pair.a, nb.index}, c1 = {e.pair.a, nb.index + 1};
      double g0 = node_gap2(an[c0.a], bn[c0.b]), g1 = node_gap2(an[c1.a], bn[c1.b]);
      if (g0 <= g1) std::swap(c0, c1), std::swap(g0, g1);  // push the farther first: the nearer is searched first
      if (!far(g0)) stack.push_back({c0, g0});
      if (!far(g1)) stack.push_back({c1, g1});
    }
  }

  // A first bound: straight down, always into the nearer child pair.
  void descend(Best& best) {
    const auto& an = A_.nodes();
    const auto& bn = B_.nodes();
    NodePair pr{0, 0};
    for (;;) {
      const Node &na = an[pr.a], &nb = bn[pr.b];
      if (na.leaf() && nb.leaf()) return leaves(na, nb, best);
      NodePair c0, c1;
      if (TriangleBvh::open_first(na, nb)) c0 = {na.index, pr.b}, c1 = {na.index + 1, pr.b};
      else c0 = {pr.a, nb.index}, c1 = {pr.a, nb.index + 1};
      pr = node_gap2(an[c0.a], bn[c0.b]) <= node_gap2(an[c1.a], bn[c1.b]) ? c0 : c1;
    }
  }

 private:
  const Side& A_;
  const Side& B_;
};

}  // namespace

PlacedMesh PlacedMesh::moved_field(const MeshField& f, const Affine3& map) {
  const std::optional<Affine3> inv = map.finite() ? map.inverse() : std::nullopt;
  if (!inv) throw InputError(f.welded().name, 0, "the map that moves the mesh is not invertible: it has no placement");
  return PlacedMesh(f, *inv);
}

double triangle_distance2(const Vec3 p[3], const Vec3 q[3], Vec3& on_p, Vec3& on_q) {
  Candidate c;
  // Vertices against edges (every endpoint case of the nine edge pairs, each once).
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      c.offer(p[i], on_segment(p[i], q[k], q[(k + 1) % 3]));
      c.offer(on_segment(q[i], p[k], p[(k + 1) % 3]), q[i]);
    }
  // Edges against edges, inside both.
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) segment_interiors(p[i], p[(i + 1) % 3], q[k], q[(k + 1) % 3], c);
  // Vertices against faces.
  const Vec3 np = cross(p[1] - p[0], p[2] - p[0]), nq = cross(q[1] - q[0], q[2] - q[0]);
  const double np2 = length2(np), nq2 = length2(nq);
  for (int i = 0; i < 3; ++i) {
    vertex_face(p[i], q, nq, nq2, true, c);
    vertex_face(q[i], p, np, np2, false, c);
  }
  on_p = c.p;
  on_q = c.q;
  return c.d2;
}

MeshPairResult compare_meshes(const PlacedMesh& pa, const PlacedMesh& pb, const MeshPairOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  FREP_ASSERT(pa.field && pb.field, "compare_meshes needs two meshes");
  for (const PlacedMesh* p : {&pa, &pb})
    if (!p->place.finite())
      throw InputError(p->field->welded().name, 0, "the placement of the mesh is not finite");
  const std::optional<Affine3> inv_a = pa.place.inverse(), inv_b = pb.place.inverse();
  if (!inv_a) throw InputError(pa.field->welded().name, 0, "the placement of the mesh is singular");
  if (!inv_b) throw InputError(pb.field->welded().name, 0, "the placement of the mesh is singular");

  // Placed coordinates, then one power of two for both so that the largest magnitude is in
  // [1/2, 1): the exact predicates' expansions neither overflow nor underflow, and no
  // predicate's sign or distance changes (only exponents do).
  Side A, B;
  A.field = pa.field;
  B.field = pb.field;
  double big = 0;
  for (auto [side, place] : {std::pair<Side*, const PlacedMesh*>{&A, &pa}, {&B, &pb}}) {
    const TriMesh& w = place->field->welded();
    side->placed.triangles = w.triangles;
    side->placed.name = w.name;
    side->placed.vertices.resize(w.vertices.size());
    const bool identity = place->place.is_identity();
    for (std::size_t i = 0; i < w.vertices.size(); ++i) {
      const Vec3 v = identity ? w.vertices[i] : place->place.apply(w.vertices[i]);
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw InputError(w.name, 0, "the placed mesh has coordinates beyond the double range");
      side->placed.vertices[i] = v;
      big = std::max({big, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    }
  }
  int exponent = 0;
  if (big > 0) std::frexp(big, &exponent);
  for (Side* s : {&A, &B})
    for (Vec3& v : s->placed.vertices) v = {std::ldexp(v.x, -exponent), std::ldexp(v.y, -exponent), std::ldexp(v.z, -exponent)};
  const auto unscale = [&](const Vec3& v) { return Vec3{std::ldexp(v.x, exponent), std::ldexp(v.y, exponent), std::ldexp(v.z, exponent)}; };

  const int threads = resolve_thread_count(opt.threads);
  parallel_for_ranges(std::min(threads, 2), 2, 1, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) (k == 0 ? A : B).index();
  });

  MeshPairResult r;
  r.a_shells = pa.field->topology().num_shells();
  r.b_shells = pb.field->topology().num_shells();
  const std::size_t want = 64 * static_cast<std::size_t>(threads);

  // Contacts: every pair of triangles whose boxes meet, classified exactly.
  {
    const std::vector<NodePair> jobs = top_pairs(A, B, want, TriangleBvh::boxes_overlap);
    std::vector<Tally> tallies(static_cast<std::size_t>(threads));
    for (Tally& t : tallies) t.keep = opt.max_examples;
    parallel_for_ranges(threads, jobs.size(), 1, [&](int worker, std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) contacts_below(A, B, jobs[k], tallies[static_cast<std::size_t>(worker)]);
    });
    std::vector<std::uint64_t> keys[3];
    for (Tally& t : tallies)
      for (int kind = 0; kind < 3; ++kind) {
        (kind == 0 ? r.crossing : kind == 1 ? r.overlapping : r.touching) += t.count[kind];
        for (; !t.first[kind].empty(); t.first[kind].pop()) keys[kind].push_back(t.first[kind].top());
      }
    // Triangle index -> leaf position, for the corners of the examples.
    std::vector<std::uint32_t> pos_a(A.tri.size()), pos_b(B.tri.size());
    for (std::uint32_t i = 0; i < A.tri.size(); ++i) pos_a[A.id(i)] = i;
    for (std::uint32_t i = 0; i < B.tri.size(); ++i) pos_b[B.id(i)] = i;
    for (int kind = 0; kind < 3; ++kind) {
      std::sort(keys[kind].begin(), keys[kind].end());
      for (std::uint64_t key : keys[kind]) {
        if (r.examples.size() >= opt.max_examples) break;
        MeshPairContactExample ex;
        ex.a = std::uint32_t(key >> 32);
        ex.b = std::uint32_t(key);
        ex.kind = static_cast<PairContact>(kind);
        ex.point = unscale(contact_point(A.tri[pos_a[ex.a]].data(), B.tri[pos_b[ex.b]].data()));
        r.examples.push_back(ex);
      }
    }
  }

  if (r.surfaces_meet()) {
    r.distance = 0;
    if (!r.examples.empty()) {
      r.point_a = r.point_b = r.examples.front().point;
      r.triangle_a = r.examples.front().a;
      r.triangle_b = r.examples.front().b;
    }
  } else {
    // Nesting: with the surfaces apart, each shell is wholly inside the other solid or wholly
    // outside it, so one vertex per shell decides. The vertex is taken to the other mesh's own
    // coordinates (exactly so when both placements are the identity) and signed there.
    const auto inside = [](const PlacedMesh& from, const PlacedMesh& to, const Affine3& to_inverse) {
      const MeshTopology& topo = from.field->topology();
      const TriMesh& w = from.field->welded();
      const Affine3 map = to_inverse * from.place;
      const bool identity = from.place.is_identity() && to.place.is_identity();
      std::size_t n = 0;
      for (std::uint32_t s = 0; s < topo.num_shells(); ++s) {
        const auto faces = topo.shell_faces(s);
        if (faces.empty()) continue;
        const Vec3 v = w.corner(faces[0], 0);
        if (to.field->signed_distance(identity ? v : map.apply(v)) < 0) ++n;
      }
      return n;
    };
    r.a_shells_inside_b = inside(pa, pb, *inv_b);
    r.b_shells_inside_a = inside(pb, pa, *inv_a);

    if (!opt.distance) {
      r.distance = std::numeric_limits<double>::quiet_NaN();
    } else {
      DistanceSearch search(A, B);
      Best first;
      search.descend(first);
      std::vector<NodePair> jobs = top_pairs(A, B, want, [](const Node&, const Node&) { return true; });
      // Nearest jobs first: they tighten the shared bound that prunes the others.
      std::vector<std::pair<double, std::size_t>> order(jobs.size());
      for (std::size_t k = 0; k < jobs.size(); ++k)
        order[k] = {node_gap2(A.nodes()[jobs[k].a], B.nodes()[jobs[k].b]), k};
      std::sort(order.begin(), order.end());
      std::vector<Best> bests(static_cast<std::size_t>(threads), first);
      parallel_for_ranges(threads, order.size(), 1, [&](int worker, std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) search.below(jobs[order[k].second], bests[static_cast<std::size_t>(worker)]);
      });
      Best best = first;
      for (const Best& b : bests)
        if (best.better(b.d2, b.a, b.b)) best = b;
      FREP_ASSERT(std::isfinite(best.d2), "no closest pair found");
      r.distance = std::ldexp(std::sqrt(best.d2), exponent);
      r.point_a = unscale(best.pa);
      r.point_b = unscale(best.pb);
      r.triangle_a = best.a;
      r.triangle_b = best.b;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace frep
