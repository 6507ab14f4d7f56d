// Mesh validation: one named check per kind of problem, all working on one welded copy of the
// mesh and its topology (mesh/topology.hpp); the report's text and JSON forms.
#include "frep/mesh/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/util/thread_pool.hpp"
#include "util/json.hpp"
#include "util/union_find.hpp"

namespace frep {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

struct KindInfo {
  const char* key;
  const char* what;
  bool fatal;
};
const KindInfo kKinds[kDefectKinds] = {
    {"open_edges", "open (boundary) edges", true},
    {"non_manifold_edges", "non-manifold edges (more than two triangles)", true},
    {"non_manifold_vertices", "non-manifold (pinched) vertices", true},
    {"inconsistent_orientation", "inconsistently oriented edges", true},
    {"inward_orientation", "inward orientation (negative volume)", true},
    {"shell_orientation", "shells with inconsistent orientation or nesting", true},
    {"degenerate_shells", "degenerate (flat, zero-volume) shells", true},
    {"self_intersections", "crossing triangle pairs (self-intersections)", true},
    {"overlaps", "coplanar overlapping or folded triangle pairs", true},
    {"duplicate_triangles", "duplicate triangles", true},
    {"zero_area_triangles", "zero-area triangles (collinear corners)", false},
    {"collapsed_triangles", "collapsed triangles (repeated vertex, ignored)", false},
    {"needle_triangles", "needle triangles", false},
    {"touching_pairs", "touching triangle pairs (boundaries meet, interiors do not)", false},
    {"unused_vertices", "unused vertices", false},
    {"duplicate_vertices", "duplicate vertices (same position, merged)", false},
};


// An edge-connected piece of the surface, as the shell checks see it.
struct Shell {
  Box3 box;
  double volume = 0;
  std::uint32_t first = kNone;
  std::uint32_t largest = kNone;  // its largest non-degenerate triangle
  double largest_n2 = 0;          // |cross|^2 of that triangle
  bool spatial = false;           // its corners are not all in one plane (exact)
};

// Contacts found by one thread of the intersection test, per kind (crossing, overlap, touching):
// a count, and the smallest (a, b) pairs seen so far in a max-heap of at most `keep`, so memory
// does not grow with the number of pairs and the examples do not depend on how pairs were
// spread over the threads.
struct alignas(64) PairTally {
  using Pair = std::uint64_t;  // a << 32 | b, a < b
  std::uint64_t count[3] = {0, 0, 0};
  std::vector<Pair> best[3];

  void add(int kind, std::uint32_t a, std::uint32_t b, std::size_t keep) {
    ++count[kind];
    if (keep == 0) return;
    const Pair key = (Pair(std::min(a, b)) << 32) | std::max(a, b);
    std::vector<Pair>& h = best[kind];
    if (h.size() < keep) {
      h.push_back(key);
      std::push_heap(h.begin(), h.end());
    } else if (key < h.front()) {
      std::pop_heap(h.begin(), h.end());
      h.back() = key;
      std::push_heap(h.begin(), h.end());
    }
  }
};

// One validation: the welded, scaled mesh, its topology, and what the checks pass on to each
// other (which triangles are flat, the shells, the intersection test's hierarchy).
class Validation {
 public:
  // With `hierarchy`, the intersection test's hierarchy is built, where it can be, as the
  // distance oracle builds its own (over every triangle, in the file's coordinates, with these
  // options), so that it can be handed on (take_products).
  Validation(const TriMesh& raw, const ValidationOptions& opt, const BvhOptions* hierarchy = nullptr);

  void check_vertices();
  void check_triangles();
  void check_duplicate_triangles();
  void check_edges();
  void check_vertex_fans();
  void check_shells();
  void check_self_intersections();
  void find_planar_regions();
  void check_shell_nesting();
  ValidationReport finish();
  // The welded mesh in the file's coordinates, its topology and, if built so, the hierarchy.
  void take_products(ValidationProducts& out);

 private:
  std::vector<std::pair<std::uint32_t, Vec3>> nesting_probes() const;
  std::vector<double> winding_numbers_at(const std::vector<std::pair<std::uint32_t, Vec3>>& probes) const;
  // True if corner k of triangle t lies in the plane of triangle u's planar region because it is
  // a corner of a triangle of that region (what the intersection test's PlaneHint asks).
  bool in_region_plane(std::uint32_t t, int k, std::uint32_t u) const {
    for (std::uint32_t f : topo_.vertex_faces(m_.triangles[t][k]))
      if (plane_[f] == plane_[u]) return true;
    return false;
  }
  struct PairInRegions {
    const Validation* v;
    std::uint32_t t[2];
  };
  // Shells whose (closed) box meets `b`, through a hierarchy over the shell boxes built once.
  void shells_meeting(const Box3& b, std::vector<std::uint32_t>& out) const;

  const TriMesh& raw_;
  const ValidationOptions& opt_;
  const BvhOptions* hierarchy_;  // see the constructor
  ValidationReport r_;
  WeldResult w_;
  const TriMesh& m_ = w_.mesh;  // welded and scaled by 2^-exponent_; triangle indices equal the file's
  int exponent_ = 0;            // the file's coordinates are m_'s times 2^exponent_
  std::vector<Vec3> unscaled_;  // m_'s vertices in the file's coordinates, when exponent_ != 0 and hierarchy_
  bool boxes_fit_float_ = false;  // all coordinates finite, the largest within 2^-60 .. 2^60
  MeshTopology topo_;  // built on the file's coordinates (its normals are the distance oracle's)
  std::vector<char> flat_;  // zero area, collapsed or a later duplicate: skipped by the intersection test
  std::vector<Shell> shells_;
  double volume_ = 0;
  std::optional<TriangleBvh> bvh_;  // of the intersection test
  bool bvh_unscaled_ = false;       // bvh_ is over the file's coordinates (and every triangle)
  std::vector<std::uint32_t> plane_;  // per triangle: its planar region (find_planar_regions)
  std::vector<std::uint32_t> bvh_triangles_;  // when bvh_ is over a subset: its triangles' indices in m_
  mutable std::optional<TriangleBvh> shell_bvh_;  // over the shell boxes (each a "triangle" from lo to hi)
  bool bvh_is_whole_ = false;       // over every triangle of m_ (then the nesting test reuses it)

  Vec3 unscale(const Vec3& p) const {
    return {std::ldexp(p.x, exponent_), std::ldexp(p.y, exponent_), std::ldexp(p.z, exponent_)};
  }
  Defect& d(DefectKind k) { return r_.defects[static_cast<int>(k)]; }
  DefectLocation at_triangle(std::uint32_t t) const {
    DefectLocation l;
    l.triangle = t;
    const FaceOrigin o = m_.origin_of(t);
    l.face = o.face;
    l.line = o.line;
    l.point = unscale((m_.corner(t, 0) + m_.corner(t, 1) + m_.corner(t, 2)) / 3.0);
    return l;
  }
  void add(DefectKind k, const DefectLocation& l) {
    Defect& x = d(k);
    ++x.count;
    if (x.examples.size() < opt_.max_examples) x.examples.push_back(l);
  }
  bool closed_manifold() {
    return d(DefectKind::OpenEdges).count == 0 && d(DefectKind::NonManifoldEdges).count == 0 &&
           d(DefectKind::NonManifoldVertices).count == 0;
  }
};

Validation::Validation(const TriMesh& raw, const ValidationOptions& opt, const BvhOptions* hierarchy)
    : raw_(raw), opt_(opt), hierarchy_(hierarchy), w_(weld(raw, {opt.weld_tolerance})) {
  r_.file = raw.name;
  r_.file_vertices = raw.vertices.size();
  r_.triangles = raw.triangles.size();
  for (int k = 0; k < kDefectKinds; ++k) r_.defects.push_back({static_cast<DefectKind>(k), 0, {}});
  r_.welded_vertices = m_.vertices.size();
  r_.box = bounding_box(m_);
  // Everything below works on coordinates scaled by a power of two (exact) so that the largest
  // magnitude is in [1/2, 1): the exact predicates' expansions neither overflow (1e200) nor
  // lose bits to underflow (1e-110), and the volume's triple products stay finite. Lengths,
  // areas and volumes are scaled back when reported.
  double big = 0;
  bool finite = true;
  for (const Vec3& v : m_.vertices)
    for (double x : {v.x, v.y, v.z})
      if (std::isfinite(x)) big = std::max(big, std::fabs(x));
      else finite = false;
  if (big > 0) std::frexp(big, &exponent_);
  boxes_fit_float_ = finite && big > 0 && exponent_ >= -60 && exponent_ <= 60;
  // The topology only reads indices, except for its normals: built on the file's coordinates,
  // it is the one the distance oracle needs (take_products).
  topo_ = MeshTopology(m_);
  if (exponent_ != 0) {
    if (hierarchy_) unscaled_ = w_.mesh.vertices;  // for take_products
    for (Vec3& v : w_.mesh.vertices) v = {std::ldexp(v.x, -exponent_), std::ldexp(v.y, -exponent_), std::ldexp(v.z, -exponent_)};
  }
  flat_.assign(m_.triangles.size(), 0);
}

// Unused vertices, and duplicates: vertices with a lower-numbered vertex at the same position
// (indexed formats only: STL repeats every corner by design). Used vertices are grouped by the
// weld (exact or within the tolerance); an unused vertex joins the group of any vertex at
// exactly its position.
void Validation::check_vertices() {
  const std::size_t nv = raw_.vertices.size();
  bool any_unused = false;
  for (std::uint32_t v = 0; v < nv; ++v) any_unused = any_unused || w_.welded_of_original[v] == kNoVertex;
  std::optional<UnionFind> same;  // only needed when unused vertices can be duplicates
  if (raw_.indexed && any_unused) {
    same.emplace(first_at_same_position(raw_.vertices));
    for (std::uint32_t v = 0; v < nv; ++v)
      if (w_.welded_of_original[v] != kNoVertex) same->unite(v, w_.original_of_welded[w_.welded_of_original[v]]);
  }
  for (std::uint32_t v = 0; v < nv; ++v) {
    DefectLocation l;
    l.vertex = v;
    l.point = raw_.vertices[v];
    const bool unused = w_.welded_of_original[v] == kNoVertex;
    if (unused) add(DefectKind::UnusedVertices, l);
    const bool duplicate =
        same ? same->find(v) != v : !unused && w_.original_of_welded[w_.welded_of_original[v]] != v;
    if (raw_.indexed && duplicate) add(DefectKind::DuplicateVertices, l);
  }
}

// Collapsed (repeated index), zero area (exactly collinear), needles; the total area.
void Validation::check_triangles() {
  for (std::uint32_t t = 0; t < m_.triangles.size(); ++t) {
    if (!topo_.usable(t)) {
      flat_[t] = 1;
      add(DefectKind::CollapsedTriangles, at_triangle(t));
      continue;
    }
    const Vec3 a = m_.corner(t, 0), b = m_.corner(t, 1), c = m_.corner(t, 2);
    const Vec3 n = cross(b - a, c - a);
    r_.area += 0.5 * length(n);
    const bool collinear = exact::orient2d(a.x, a.y, b.x, b.y, c.x, c.y) == 0 &&
                           exact::orient2d(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
                           exact::orient2d(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
    if (collinear) {
      flat_[t] = 1;
      add(DefectKind::ZeroAreaTriangles, at_triangle(t));
      continue;
    }
    const double e2 = length2(b - a) + length2(c - b) + length2(a - c);
    if (4 * std::sqrt(3.0) * 0.5 * length(n) < opt_.needle_quality * e2) add(DefectKind::NeedleTriangles, at_triangle(t));
  }
}

// Duplicate triangles: same vertex set as an earlier triangle. Sorted once; each run of equal
// keys names its first triangle. Copies are left out of the intersection test, where they
// would pair with every other copy.
void Validation::check_duplicate_triangles() {
  std::vector<std::pair<Triangle, std::uint32_t>> keys;
  keys.reserve(m_.triangles.size());
  for (std::uint32_t t = 0; t < m_.triangles.size(); ++t)
    if (topo_.usable(t)) {
      Triangle s = m_.triangles[t];
      std::sort(s.begin(), s.end());
      keys.push_back({s, t});
    }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 0, j; i < keys.size(); i = j) {
    for (j = i + 1; j < keys.size() && keys[j].first == keys[i].first; ++j) {
      DefectLocation l = at_triangle(keys[j].second);
      l.other = keys[i].second;
      add(DefectKind::DuplicateTriangles, l);
      flat_[keys[j].second] = 1;
    }
  }
}

// Open edges (one triangle), non-manifold edges (more than two), inconsistent orientation (two
// triangles traversing the edge the same way).
void Validation::check_edges() {
  r_.edges = topo_.num_edges();
  for (std::uint32_t e = 0; e < topo_.num_edges(); ++e) {
    const auto faces = topo_.edge_faces(e);
    if (faces.size() == 2 && topo_.consistent(e)) continue;
    const auto [a, b] = topo_.edge_vertices(e);
    DefectLocation l = at_triangle(faces[0]);
    l.point = unscale((m_.vertices[a] + m_.vertices[b]) * 0.5);
    l.vertex = w_.original_of_welded[a];
    if (faces.size() > 1) l.other = faces[1];
    add(faces.size() == 1   ? DefectKind::OpenEdges
        : faces.size() > 2 ? DefectKind::NonManifoldEdges
                           : DefectKind::InconsistentOrientation,
        l);
  }
}

// Non-manifold vertices: the triangles around a vertex, joined through manifold edges at it,
// must form a single fan.
void Validation::check_vertex_fans() {
  for (std::uint32_t v = 0; v < topo_.num_vertices(); ++v) {
    if (!topo_.pinched(v)) continue;
    DefectLocation l = at_triangle(topo_.vertex_faces(v)[0]);
    l.vertex = w_.original_of_welded[v];
    l.point = unscale(m_.vertices[v]);
    add(DefectKind::NonManifoldVertices, l);
  }
}

// Shells: boxes, and signed volumes summed about the shell's box center rather than the origin,
// where far from the origin the tetrahedra cancel catastrophically (a unit sphere at 1e6 came
// out with the wrong sign). On a closed, manifold, consistently oriented surface: the genus,
// shells that enclose no volume, and a negative total volume.
void Validation::check_shells() {
  shells_.resize(topo_.num_shells());
  r_.components = shells_.size();
  for (std::uint32_t i = 0; i < shells_.size(); ++i) {
    Shell& s = shells_[i];
    const auto faces = topo_.shell_faces(i);
    s.first = faces[0];
    for (std::uint32_t t : faces)
      for (std::uint32_t v : m_.triangles[t]) s.box.add(m_.vertices[v]);
    const Vec3 o = s.box.center();
    for (std::uint32_t t : faces) {
      const Vec3 a = m_.corner(t, 0) - o, b = m_.corner(t, 1) - o, c = m_.corner(t, 2) - o;
      s.volume += dot(a, cross(b, c)) / 6.0;
      if (flat_[t]) continue;
      const double n2 = length2(cross(b - a, c - a));
      if (s.largest == kNone || n2 > s.largest_n2) s.largest = t, s.largest_n2 = n2;
    }
    // A shell encloses volume only if its corners span space: compare every corner with the
    // plane of the shell's largest triangle until one is off it (usually the first few).
    if (s.largest == kNone) continue;
    const Vec3 a = m_.corner(s.largest, 0), b = m_.corner(s.largest, 1), c = m_.corner(s.largest, 2);
    for (std::size_t k = 0; k < faces.size() && !s.spatial; ++k)
      for (int j = 0; j < 3 && !s.spatial; ++j) s.spatial = exact::orient3d(a, b, c, m_.corner(faces[k], j)) != 0;
  }
  for (const Shell& s : shells_) volume_ += s.volume;

  if (!closed_manifold() || d(DefectKind::InconsistentOrientation).count != 0) return;
  r_.genus = (2 * std::int64_t(r_.components) - topo_.euler_characteristic()) / 2;
  // Each shell must enclose volume; with several, their orientations and nesting are checked
  // by winding numbers once it is known that they do not cross (check_shell_nesting).
  for (const Shell& s : shells_)
    if (s.largest == kNone || !s.spatial || s.volume == 0) add(DefectKind::DegenerateShells, at_triangle(s.first));
  if (volume_ < 0) {
    DefectLocation l;
    if (shells_.size() == 1) l = at_triangle(shells_[0].first);
    else l.point = r_.box.lo * 0.5 + r_.box.hi * 0.5;
    add(DefectKind::InwardOrientation, l);
  }
}

// Self-intersections: candidate pairs from a hierarchy over the triangles that can intersect
// anything, classified exactly: crossing, coplanar overlap (or fold), touching. Pairs within one
// planar region are classified as coplanar without their orientation signs (see plane_).
void Validation::check_self_intersections() {
  const std::size_t nt = m_.triangles.size();
  if (!opt_.self_intersections || nt <= 1) return;
  r_.self_intersections_checked = true;
  std::vector<std::uint32_t> live;
  for (std::uint32_t t = 0; t < nt; ++t)
    if (!flat_[t]) live.push_back(t);
  bvh_is_whole_ = live.size() == nt;
  if (bvh_is_whole_ && hierarchy_ && boxes_fit_float_) {
    // The distance oracle's hierarchy, over the file's coordinates. Its single-precision boxes
    // hold their triangles as the scaled ones do (coordinates within 2^+-60 keep them tight),
    // and any hierarchy finds every pair whose boxes overlap: the same pairs meet.
    if (exponent_ != 0) w_.mesh.vertices.swap(unscaled_);
    bvh_.emplace(m_, *hierarchy_);
    if (exponent_ != 0) w_.mesh.vertices.swap(unscaled_);
    bvh_unscaled_ = true;
  } else if (bvh_is_whole_) {
    bvh_.emplace(m_);
  } else {
    TriMesh sub;
    sub.vertices = m_.vertices;
    for (std::uint32_t t : live) sub.triangles.push_back(m_.triangles[t]);
    bvh_.emplace(sub);
    bvh_triangles_ = live;
  }
  find_planar_regions();
  const int threads = std::min(resolve_thread_count(opt_.threads), 1024);
  std::vector<PairTally> found(threads);
  const bool subset = !bvh_triangles_.empty();
  bvh_->for_each_overlapping_pair_parallel(threads, [&](std::uint32_t a, std::uint32_t b, int th) {
    if (subset) a = live[a], b = live[b];
    const Triangle &ta = m_.triangles[a], &tb = m_.triangles[b];
    const Vec3 p[3] = {m_.vertices[ta[0]], m_.vertices[ta[1]], m_.vertices[ta[2]]};
    const Vec3 q[3] = {m_.vertices[tb[0]], m_.vertices[tb[1]], m_.vertices[tb[2]]};
    const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
    const PairInRegions pair{this, {a, b}};
    const PlaneHint hint{[](const void* c, int which, int k) {
                           const auto& x = *static_cast<const PairInRegions*>(c);
                           return x.v->in_region_plane(x.t[which], k, x.t[1 - which]);
                         },
                         &pair};
    const Contact k = classify_triangle_pair(p, pi, q, qi, plane_[a] == plane_[b], &hint);
    if (k != Contact::None) found[th].add(k == Contact::Cross ? 0 : (k == Contact::Overlap ? 1 : 2), a, b, opt_.max_examples);
  });
  const DefectKind kinds[3] = {DefectKind::SelfIntersections, DefectKind::Overlaps, DefectKind::TouchingPairs};
  for (int kind = 0; kind < 3; ++kind) {
    std::vector<PairTally::Pair> all;
    Defect& x = d(kinds[kind]);
    for (const PairTally& f : found) {
      x.count += f.count[kind];
      all.insert(all.end(), f.best[kind].begin(), f.best[kind].end());
    }
    std::sort(all.begin(), all.end());
    for (std::size_t i = 0; i < all.size() && x.examples.size() < opt_.max_examples; ++i) {
      DefectLocation l = at_triangle(std::uint32_t(all[i] >> 32));
      l.other = std::uint32_t(all[i]);
      x.examples.push_back(l);
    }
  }
}

// Planar regions: non-flat triangles joined through edges of exactly two non-flat triangles
// that lie in one plane (exact orient3d). Non-flat triangles span a plane each, so a region lies
// in one plane, and every pair within it is coplanar: on CAD parts, flat faces tessellated into
// fans, that is most candidate pairs, whose orientation signs are zeros the predicates' float
// filter cannot certify (their exact stage was most of the test's time). A region only needs to
// be coplanar, not as large as can be: edges whose face normals (the topology's, in floating
// point) are clearly not parallel are not tested, which on smooth meshes is nearly all of them.
void Validation::find_planar_regions() {
  const std::size_t nt = m_.triangles.size();
  // The edges are tested in parallel (each from its first triangle), the regions joined after.
  const int threads = std::min(resolve_thread_count(opt_.threads), 1024);
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> joined(threads);
  parallel_for_ranges(threads, nt, 8192, [&](int worker, std::size_t begin, std::size_t end) {
    for (auto t = static_cast<std::uint32_t>(begin); t < end; ++t) {
      if (flat_[t]) continue;
      const Triangle& f = m_.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = topo_.triangle_edges(t)[k];
        if (topo_.edge_face_count(e) != 2 || topo_.edge_faces(e)[0] != t) continue;
        const std::uint32_t g = topo_.edge_faces(e)[1];
        if (flat_[g] || std::fabs(dot(topo_.face_normal(t), topo_.face_normal(g))) < 1 - 1e-9) continue;
        // g's corner off the edge (which joins f's corners k and k + 1).
        const Triangle& gt = m_.triangles[g];
        const std::uint32_t a = f[k], b = f[(k + 1) % 3];
        const std::uint32_t w = gt[0] != a && gt[0] != b ? gt[0] : (gt[1] != a && gt[1] != b ? gt[1] : gt[2]);
        if (exact::orient3d(m_.vertices[f[0]], m_.vertices[f[1]], m_.vertices[f[2]], m_.vertices[w]) == 0)
          joined[worker].push_back({t, g});
      }
    }
  });
  UnionFind regions(nt);  // roots are the smallest members, whatever the order
  for (const auto& list : joined)
    for (const auto& [t, g] : list) regions.unite(t, g);
  plane_ = std::move(regions).roots();  // flat triangles are regions of their own, and never in a pair
}

// Several closed, consistently oriented shells that do not cross: just outside each shell's
// largest triangle (on its normal's side) the winding number of the whole mesh must be 0. It
// is -1 there for an inward shell that is not a cavity, and 2 - 1 = 1 for an outward shell
// nested in another outward one (or a cavity inside a cavity).
void Validation::check_shell_nesting() {
  if (!closed_manifold() || d(DefectKind::InconsistentOrientation).count != 0 || shells_.size() <= 1 ||
      d(DefectKind::SelfIntersections).count != 0 || d(DefectKind::Overlaps).count != 0)
    return;
  const std::vector<std::pair<std::uint32_t, Vec3>> probes = nesting_probes();
  const std::vector<double> wn = winding_numbers_at(probes);
  for (std::size_t k = 0; k < probes.size(); ++k)
    if (!(std::fabs(wn[k]) < 0.5)) add(DefectKind::ShellOrientation, at_triangle(shells_[probes[k].first].largest));
}

// Per shell that spans space: a point just off its largest triangle, on the normal's side. The
// offset from the centroid is a small fraction of the inradius (|n| / perimeter), doubled until
// the point is strictly on that side by the exact predicate.
std::vector<std::pair<std::uint32_t, Vec3>> Validation::nesting_probes() const {
  std::vector<std::pair<std::uint32_t, Vec3>> probes;  // (shell, point)
  // True if the segment from g (on triangle `own`) to p meets another triangle of a shell whose
  // box meets the segment's (exact; touching counts): the probe went through a wall thinner than
  // its offset.
  // A budget of triangle visits over all probes (like the winding numbers' exact sums): beyond
  // it, probes are taken as they are (a wall thinner than 1e-3 of a triangle's inradius is rare).
  std::uint64_t budget = std::uint64_t(1) << 26;
  std::vector<std::uint32_t> near;
  const auto crosses_a_wall = [&](const Vec3& g, const Vec3& p, std::uint32_t own) {
    Box3 seg;
    seg.add(g);
    seg.add(p);
    // Candidates: from the intersection test's hierarchy when there is one, else every triangle
    // of the shells whose boxes meet the segment's (within the budget).
    near.clear();
    if (bvh_) {
      // A hierarchy over the file's coordinates is asked about the segment's box there, rounded
      // outward (it holds every point of the scaled box, scaled back).
      Box3 query = seg;
      if (bvh_unscaled_ && exponent_ != 0)
        for (int k = 0; k < 3; ++k) {
          query.lo[k] = std::nextafter(std::ldexp(seg.lo[k], exponent_), -INFINITY);
          query.hi[k] = std::nextafter(std::ldexp(seg.hi[k], exponent_), INFINITY);
        }
      bvh_->for_each_meeting(query, [&](std::uint32_t t) { near.push_back(bvh_triangles_.empty() ? t : bvh_triangles_[t]); });
    } else {
      std::vector<std::uint32_t> shells;
      shells_meeting(seg, shells);
      for (std::uint32_t j : shells) {
        const auto faces = topo_.shell_faces(j);
        if (budget < faces.size()) return false;
        budget -= faces.size();
        near.insert(near.end(), faces.begin(), faces.end());
      }
    }
    for (std::uint32_t t : near) {
      if (t == own || flat_[t]) continue;
      const Vec3 A = m_.corner(t, 0), B = m_.corner(t, 1), C = m_.corner(t, 2);
      Box3 tb;
      tb.add(A), tb.add(B), tb.add(C);
      if (!tb.meets(seg)) continue;
      const int s1 = exact::orient3d(A, B, C, g), s2 = exact::orient3d(A, B, C, p);
      if (s1 != 0 && s1 == s2) continue;
      const int e0 = exact::orient3d(g, p, A, B), e1 = exact::orient3d(g, p, B, C), e2 = exact::orient3d(g, p, C, A);
      if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0)) return true;
    }
    return false;
  };
  for (std::uint32_t i = 0; i < shells_.size(); ++i) {
    const Shell& s = shells_[i];
    if (s.largest == kNone || !s.spatial) continue;
    const Vec3 a = m_.corner(s.largest, 0), b = m_.corner(s.largest, 1), c = m_.corner(s.largest, 2);
    const Vec3 n = cross(b - a, c - a), g = (a + b + c) / 3.0;
    double delta = 1e-3 * length(n) / (length(b - a) + length(c - b) + length(a - c));
    const Vec3 u = n / length(n);
    // Strictly on the normal's side (doubling the offset), and before any other wall (halving it
    // again: a flat bubble 1e-5 thick was reported as wrongly nested when the probe crossed it).
    for (int it = 0; it < 64; ++it, delta *= 2) {
      const Vec3 p = g + u * delta;
      if (exact::orient3d(a, b, c, p) > 0) break;
    }
    for (int it = 0; it < 64; ++it, delta *= 0.25) {
      const Vec3 p = g + u * delta;
      if (!(exact::orient3d(a, b, c, p) > 0)) break;  // too close to tell: no probe for this shell
      if (!crosses_a_wall(g, p, s.largest)) {
        probes.push_back({i, p});
        break;
      }
    }
  }
  return probes;
}

// The whole mesh's winding number at each probe. A closed shell's winding number is 0 outside
// its box, so only the shells whose boxes contain a probe count: found through a hierarchy over
// the shell boxes (each box as a "triangle" from its low to its high corner), then summed
// exactly over their triangles. Disjoint shells cost about one pass over the mesh; if nesting
// makes the exact sums too expensive, the hierarchical (far-field dipole) winding number of the
// whole mesh is used, built on the welded mesh, its topology and, if it covers every triangle,
// the intersection test's hierarchy.
void Validation::shells_meeting(const Box3& b, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (!shell_bvh_) {
    TriMesh box_mesh;
    for (std::uint32_t i = 0; i < shells_.size(); ++i) {
      box_mesh.vertices.push_back(shells_[i].box.lo);
      box_mesh.vertices.push_back(shells_[i].box.hi);
      box_mesh.triangles.push_back({2 * i, 2 * i + 1, 2 * i});
    }
    shell_bvh_.emplace(box_mesh);
  }
  shell_bvh_->for_each_meeting(b, [&](std::uint32_t j) {
    if (shells_[j].box.meets(b)) out.push_back(j);
  });
}

std::vector<double> Validation::winding_numbers_at(const std::vector<std::pair<std::uint32_t, Vec3>>& probes) const {
  std::vector<std::size_t> live_faces(shells_.size(), 0);  // per shell: triangles not flat
  for (std::uint32_t i = 0; i < shells_.size(); ++i)
    for (std::uint32_t t : topo_.shell_faces(i)) live_faces[i] += !flat_[t];
  std::vector<std::vector<std::uint32_t>> around(probes.size());  // shells whose box holds the probe
  std::size_t work = 0;
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const Vec3& p = probes[k].second;
    shells_meeting(Box3{p, p}, around[k]);
    for (std::uint32_t j : around[k]) work += live_faces[j];
  }
  std::vector<double> wn(probes.size(), 0.0);
  if (work <= (std::size_t(1) << 23)) {
    for (std::size_t k = 0; k < probes.size(); ++k) {
      double sum = 0;
      for (std::uint32_t j : around[k])
        for (std::uint32_t t : topo_.shell_faces(j))
          if (!flat_[t]) sum += solid_angle(probes[k].second, m_.corner(t, 0), m_.corner(t, 1), m_.corner(t, 2));
      wn[k] = sum / (4 * 3.14159265358979323846);
    }
  } else {
    // As always: over the scaled mesh, through the intersection test's hierarchy if it covers
    // every triangle (built again over the scaled coordinates if it was built for the oracle).
    std::optional<TriangleBvh> scaled;
    if (bvh_is_whole_ && bvh_unscaled_) scaled.emplace(m_);
    const TriangleBvh* whole = !bvh_is_whole_ ? nullptr : (scaled ? &*scaled : &*bvh_);
    const MeshDistance md(m_, topo_, {}, whole);
    for (std::size_t k = 0; k < probes.size(); ++k) wn[k] = md.winding_number(probes[k].second);
  }
  return wn;
}

ValidationReport Validation::finish() {
  r_.area = std::ldexp(r_.area, 2 * exponent_);
  r_.volume = std::ldexp(volume_, 3 * exponent_);
  return std::move(r_);
}

void Validation::take_products(ValidationProducts& out) {
  if (exponent_ != 0) w_.mesh.vertices.swap(unscaled_);
  out.welded = std::move(w_.mesh);
  out.topology = std::move(topo_);
  out.hierarchy.reset();
  if (bvh_unscaled_) out.hierarchy = std::move(bvh_);
}

}  // namespace

const char* defect_key(DefectKind k) { return kKinds[static_cast<int>(k)].key; }
const char* defect_description(DefectKind k) { return kKinds[static_cast<int>(k)].what; }
bool defect_is_fatal(DefectKind k) { return kKinds[static_cast<int>(k)].fatal; }

namespace {
void run_checks(Validation& v) {
  v.check_vertices();
  v.check_triangles();
  v.check_duplicate_triangles();
  v.check_edges();
  v.check_vertex_fans();
  v.check_shells();
  v.check_self_intersections();
  v.check_shell_nesting();
}
}  // namespace

ValidationReport validate_mesh(const TriMesh& raw, const ValidationOptions& opt) {
  Validation v(raw, opt);
  run_checks(v);
  return v.finish();
}

ValidationReport validate_mesh(const TriMesh& raw, const ValidationOptions& opt, const BvhOptions& hierarchy,
                               ValidationProducts& products) {
  Validation v(raw, opt, &hierarchy);
  run_checks(v);
  ValidationReport r = v.finish();
  v.take_products(products);
  return r;
}

bool ValidationReport::is_solid() const {
  if (triangles == 0 || components == 0) return false;
  for (const Defect& d : defects)
    if (defect_is_fatal(d.kind) && d.count > 0) return false;
  return true;
}

namespace {
std::string fmt_g(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}
std::string fmt_point(const Vec3& p) { return "(" + fmt_g(p.x) + ", " + fmt_g(p.y) + ", " + fmt_g(p.z) + ")"; }
}  // namespace

std::string ValidationReport::summary() const {
  std::string s;
  if (is_solid()) {
    s = "valid solid: " + std::to_string(triangles) + " triangles, " + std::to_string(components) + " component" +
        (components == 1 ? "" : "s");
    if (genus) s += ", genus " + std::to_string(*genus);
    s += ", volume " + fmt_g(volume);
    if (!self_intersections_checked) s += " (self-intersections not checked)";
    return s;
  }
  s = "not a solid:";
  bool first = true;
  for (const Defect& d : defects)
    if (defect_is_fatal(d.kind) && d.count > 0) {
      s += (first ? " " : ", ") + std::to_string(d.count) + " " + defect_description(d.kind);
      first = false;
    }
  if (triangles == 0) s += " no triangles";
  else if (components == 0) s += " no triangles with three distinct vertices";
  return s;
}

std::string ValidationReport::to_text() const {
  std::string s = file + ": " + std::to_string(triangles) + " triangles, " + std::to_string(file_vertices) +
                  " vertices in the file, " + std::to_string(welded_vertices) + " after welding, " +
                  std::to_string(edges) + " edges\n";
  s += "  components: " + std::to_string(components);
  s += genus ? ", genus: " + std::to_string(*genus) : std::string(", genus: n/a (not a closed manifold)");
  s += "\n  volume: " + fmt_g(volume) + ", area: " + fmt_g(area) + ", box: " + fmt_point(box.lo) + " - " +
       fmt_point(box.hi) + "\n";
  if (!self_intersections_checked) s += "  self-intersections: not checked\n";
  for (const Defect& d : defects) {
    if (d.count == 0) continue;
    s += std::string(defect_is_fatal(d.kind) ? "  ERROR " : "  warning ") + defect_description(d.kind) + ": " +
         std::to_string(d.count) + "\n";
    for (const DefectLocation& l : d.examples) {
      s += "    ";
      if (l.triangle != kNone) {
        s += "triangle " + std::to_string(l.triangle);
        if (l.face != kNone && l.face != l.triangle) s += " (face " + std::to_string(l.face) + ")";
        if (l.line) s += " (line " + std::to_string(l.line) + ")";
        if (l.other != kNone) s += " and triangle " + std::to_string(l.other);
        s += " ";
      }
      if (l.vertex != kNone && (d.kind == DefectKind::NonManifoldVertices || d.kind == DefectKind::UnusedVertices ||
                                d.kind == DefectKind::DuplicateVertices))
        s += "vertex " + std::to_string(l.vertex) + " ";
      s += "at " + fmt_point(l.point) + "\n";
    }
  }
  s += summary() + "\n";
  return s;
}

std::string ValidationReport::to_json() const {
  std::string s = "{\n  \"file\": \"" + json_escape(file) + "\",\n";
  s += "  \"solid\": " + std::string(is_solid() ? "true" : "false") + ",\n";
  s += "  \"summary\": \"" + json_escape(summary()) + "\",\n";
  s += "  \"triangles\": " + std::to_string(triangles) + ",\n  \"file_vertices\": " + std::to_string(file_vertices) +
       ",\n  \"welded_vertices\": " + std::to_string(welded_vertices) + ",\n  \"edges\": " + std::to_string(edges) +
       ",\n  \"components\": " + std::to_string(components) + ",\n  \"genus\": " +
       (genus ? std::to_string(*genus) : std::string("null")) + ",\n  \"volume\": " + json_num(volume) +
       ",\n  \"area\": " + json_num(area) + ",\n  \"box\": [[" + json_num(box.lo.x) + ", " + json_num(box.lo.y) +
       ", " + json_num(box.lo.z) + "], [" + json_num(box.hi.x) + ", " + json_num(box.hi.y) + ", " +
       json_num(box.hi.z) + "]],\n  \"self_intersections_checked\": " + (self_intersections_checked ? "true" : "false") +
       ",\n  \"defects\": {\n";
  for (std::size_t i = 0; i < defects.size(); ++i) {
    const Defect& d = defects[i];
    s += "    \"" + std::string(defect_key(d.kind)) + "\": {\"count\": " + std::to_string(d.count) +
         ", \"fatal\": " + (defect_is_fatal(d.kind) ? "true" : "false") + ", \"examples\": [";
    for (std::size_t k = 0; k < d.examples.size(); ++k) {
      const DefectLocation& l = d.examples[k];
      s += k ? ", {" : "{";
      std::string sep;
      auto field = [&](const char* name, std::uint32_t v) {
        if (v == kNone) return;
        s += sep + "\"" + name + "\": " + std::to_string(v);
        sep = ", ";
      };
      field("triangle", l.triangle);
      field("other", l.other);
      field("vertex", l.vertex);
      field("face", l.face);
      if (l.line) field("line", l.line);
      s += sep + "\"point\": [" + json_num(l.point.x) + ", " + json_num(l.point.y) + ", " + json_num(l.point.z) + "]}";
    }
    s += "]}" + std::string(i + 1 < defects.size() ? ",\n" : "\n");
  }
  s += "  }\n}\n";
  return s;
}

}  // namespace frep
