#include "frep/mesh/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numeric>

#include "frep/error.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/util/thread_pool.hpp"
#include "predicates.hpp"
#include "tri_tri.hpp"

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

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : p_(n) { std::iota(p_.begin(), p_.end(), 0u); }
  std::uint32_t find(std::uint32_t i) {
    while (p_[i] != i) i = p_[i] = p_[p_[i]];
    return i;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) p_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::uint32_t> p_;
};

struct Collector {
  ValidationReport& r;
  const TriMesh& m;  // welded and scaled by 2^-exponent; triangle indices equal the file's
  const std::vector<std::uint32_t>& original_of_welded;
  std::size_t max_examples;
  int exponent;  // the file's coordinates are m's times 2^exponent

  Vec3 unscale(const Vec3& p) const {
    return {std::ldexp(p.x, exponent), std::ldexp(p.y, exponent), std::ldexp(p.z, exponent)};
  }

  Defect& d(DefectKind k) { return r.defects[static_cast<int>(k)]; }
  DefectLocation at_triangle(std::uint32_t t) const {
    DefectLocation l;
    l.triangle = t;
    const FaceOrigin o = m.origin_of(t);
    l.face = o.face;
    l.line = o.line;
    l.point = unscale((m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)) / 3.0);
    return l;
  }
  void add(DefectKind k, const DefectLocation& l) {
    Defect& x = d(k);
    ++x.count;
    if (x.examples.size() < max_examples) x.examples.push_back(l);
  }
};

// Signed solid angle of triangle abc seen from p (Van Oosterom and Strackee), positive when p is
// on the side opposite to the right-hand normal: sums to 4 pi inside a closed outward surface.
double solid_angle(const Vec3& p, const Vec3& a0, const Vec3& b0, const Vec3& c0) {
  const Vec3 a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = length(a), lb = length(b), lc = length(c);
  const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2 * std::atan2(dot(a, cross(b, c)), den);
}

}  // namespace

const char* defect_key(DefectKind k) { return kKinds[static_cast<int>(k)].key; }
const char* defect_description(DefectKind k) { return kKinds[static_cast<int>(k)].what; }
bool defect_is_fatal(DefectKind k) { return kKinds[static_cast<int>(k)].fatal; }

ValidationReport validate_mesh(const TriMesh& raw, const ValidationOptions& opt) {
  ValidationReport r;
  r.file = raw.name;
  r.file_vertices = raw.vertices.size();
  r.triangles = raw.triangles.size();
  for (int k = 0; k < kDefectKinds; ++k) r.defects.push_back({static_cast<DefectKind>(k), 0, {}});

  WeldResult w = weld(raw, {opt.weld_tolerance});
  TriMesh& m = w.mesh;
  r.welded_vertices = m.vertices.size();
  r.box = bounding_box(m);
  // Everything below works on coordinates scaled by a power of two (exact) so that the largest
  // magnitude is in [1/2, 1): the exact predicates' expansions neither overflow (1e200) nor
  // lose bits to underflow (1e-110), and the volume's triple products stay finite. Lengths,
  // areas and volumes are scaled back when reported.
  int exponent = 0;
  {
    double big = 0;
    for (const Vec3& v : m.vertices)
      for (double x : {v.x, v.y, v.z})
        if (std::isfinite(x)) big = std::max(big, std::fabs(x));
    if (big > 0) std::frexp(big, &exponent);
    if (exponent != 0)
      for (Vec3& v : m.vertices) v = {std::ldexp(v.x, -exponent), std::ldexp(v.y, -exponent), std::ldexp(v.z, -exponent)};
  }
  Collector c{r, m, w.original_of_welded, opt.max_examples, exponent};
  const std::size_t nt = m.triangles.size(), nv = m.vertices.size();

  // Vertices: unused in the file, and duplicates merged by welding.
  for (std::uint32_t v = 0; v < raw.vertices.size(); ++v) {
    if (w.welded_of_original[v] == kNoVertex) {
      DefectLocation l;
      l.vertex = v;
      l.point = raw.vertices[v];
      c.add(DefectKind::UnusedVertices, l);
    } else if (w.original_of_welded[w.welded_of_original[v]] != v) {
      DefectLocation l;
      l.vertex = v;
      l.point = raw.vertices[v];
      // STL repeats every corner by design; only indexed formats have "duplicate" vertices.
      if (raw.indexed) c.add(DefectKind::DuplicateVertices, l);
    }
  }

  // Triangles: collapsed (repeated index), zero area (exactly collinear), needles; area.
  std::vector<char> usable(nt, 1);  // non-collapsed: take part in topology
  std::vector<char> flat(nt, 0);    // zero area or a duplicate: skipped by the intersection test
  for (std::uint32_t t = 0; t < nt; ++t) {
    const Triangle& tr = m.triangles[t];
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2]) {
      usable[t] = 0;
      flat[t] = 1;
      c.add(DefectKind::CollapsedTriangles, c.at_triangle(t));
      continue;
    }
    const Vec3 a = m.vertices[tr[0]], b = m.vertices[tr[1]], cc = m.vertices[tr[2]];
    const Vec3 n = cross(b - a, cc - a);
    r.area += 0.5 * length(n);
    const bool collinear = exact::orient2d(a.x, a.y, b.x, b.y, cc.x, cc.y) == 0 &&
                           exact::orient2d(a.y, a.z, b.y, b.z, cc.y, cc.z) == 0 &&
                           exact::orient2d(a.z, a.x, b.z, b.x, cc.z, cc.x) == 0;
    if (collinear) {
      flat[t] = 1;
      c.add(DefectKind::ZeroAreaTriangles, c.at_triangle(t));
      continue;
    }
    const double e2 = length2(b - a) + length2(cc - b) + length2(a - cc);
    if (4 * std::sqrt(3.0) * 0.5 * length(n) < opt.needle_quality * e2) c.add(DefectKind::NeedleTriangles, c.at_triangle(t));
  }

  // Duplicate triangles: same vertex set as an earlier triangle. Sorted once; each run of equal
  // keys names its first triangle. Copies are left out of the intersection test, where they
  // would pair with every other copy.
  {
    std::vector<std::pair<Triangle, std::uint32_t>> keys;
    keys.reserve(nt);
    for (std::uint32_t t = 0; t < nt; ++t)
      if (usable[t]) {
        Triangle s = m.triangles[t];
        std::sort(s.begin(), s.end());
        keys.push_back({s, t});
      }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0, j; i < keys.size(); i = j) {
      for (j = i + 1; j < keys.size() && keys[j].first == keys[i].first; ++j) {
        DefectLocation l = c.at_triangle(keys[j].second);
        l.other = keys[i].second;
        c.add(DefectKind::DuplicateTriangles, l);
        flat[keys[j].second] = 1;
      }
    }
  }

  // Edges: sort directed half-edges by their undirected key.
  struct HalfEdge {
    std::uint64_t key;  // min << 32 | max
    std::uint32_t tri;
    std::uint8_t forward;  // traversed min -> max
    bool operator<(const HalfEdge& o) const { return key != o.key ? key < o.key : tri < o.tri; }
  };
  std::vector<HalfEdge> he;
  he.reserve(3 * nt);
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (!usable[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
      he.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, std::uint8_t(a < b)});
    }
  }
  std::sort(he.begin(), he.end());
  UnionFind comp(nt);
  // Manifold edges (exactly two triangles) link the fans around their endpoints.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> fan_links;  // (vertex << 32 | other end, tri)
  std::vector<char> vertex_on_edge_defect(nv, 0);
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i;
    while (j < he.size() && he[j].key == he[i].key) ++j;
    const std::size_t count = j - i;
    ++r.edges;
    const std::uint32_t a = std::uint32_t(he[i].key >> 32), b = std::uint32_t(he[i].key);
    auto loc = [&] {
      DefectLocation l = c.at_triangle(he[i].tri);
      l.point = c.unscale((m.vertices[a] + m.vertices[b]) * 0.5);
      l.vertex = w.original_of_welded[a];
      if (count > 1) l.other = he[i + 1].tri;
      return l;
    };
    for (std::size_t k = i + 1; k < j; ++k) comp.unite(he[i].tri, he[k].tri);
    if (count == 1) {
      c.add(DefectKind::OpenEdges, loc());
    } else if (count > 2) {
      c.add(DefectKind::NonManifoldEdges, loc());
    } else {
      if (he[i].forward == he[i + 1].forward) c.add(DefectKind::InconsistentOrientation, loc());
      for (std::size_t k = i; k < j; ++k) {
        fan_links.push_back({(std::uint64_t(a) << 32) | b, he[k].tri});
        fan_links.push_back({(std::uint64_t(b) << 32) | a, he[k].tri});
      }
    }
    i = j;
  }
  // Shells (edge-connected pieces): dense ids in order of their first triangle (the union-find
  // root is the smallest triangle index), boxes, and signed volumes summed about the shell's box
  // center rather than the origin, where far from the origin the tetrahedra cancel
  // catastrophically (a unit sphere at 1e6 came out with the wrong sign).
  struct Shell {
    Box3 box;
    double volume = 0;
    std::uint32_t first = kNone;
    std::uint32_t largest = kNone;  // its largest non-degenerate triangle
    double largest_n2 = 0;          // |cross|^2 of that triangle
    bool spatial = false;           // its corners are not all in one plane (exact)
  };
  std::vector<Shell> shells;
  std::vector<std::uint32_t> shell_of(nt, kNone);
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (!usable[t]) continue;
    const std::uint32_t root = comp.find(t);
    if (root == t) {
      shell_of[t] = std::uint32_t(shells.size());
      shells.emplace_back().first = t;
    } else {
      shell_of[t] = shell_of[root];
    }
    for (std::uint32_t v : m.triangles[t]) shells[shell_of[t]].box.add(m.vertices[v]);
  }
  r.components = shells.size();
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (!usable[t]) continue;
    Shell& s = shells[shell_of[t]];
    const Vec3 o = s.box.center();
    const Vec3 a = m.corner(t, 0) - o, b = m.corner(t, 1) - o, cc = m.corner(t, 2) - o;
    s.volume += dot(a, cross(b, cc)) / 6.0;
    if (flat[t]) continue;
    const double n2 = length2(cross(b - a, cc - a));
    if (s.largest == kNone || n2 > s.largest_n2) s.largest = t, s.largest_n2 = n2;
  }
  // A shell encloses volume only if its corners span space: compare every corner with the plane
  // of the shell's largest triangle until one is off it (usually the first few).
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (!usable[t]) continue;
    Shell& s = shells[shell_of[t]];
    if (s.spatial || s.largest == kNone) continue;
    const Vec3 a = m.corner(s.largest, 0), b = m.corner(s.largest, 1), cc = m.corner(s.largest, 2);
    for (int k = 0; k < 3 && !s.spatial; ++k) s.spatial = exact::orient3d(a, b, cc, m.corner(t, k)) != 0;
  }
  double volume = 0;
  for (const Shell& s : shells) volume += s.volume;

  // Non-manifold vertices: the triangles around a vertex, joined through manifold edges at it,
  // must form a single fan.
  {
    std::vector<std::uint32_t> first(nv + 1, 0);
    for (std::uint32_t t = 0; t < nt; ++t)
      if (usable[t])
        for (std::uint32_t v : m.triangles[t]) ++first[v + 1];
    for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1), incident(first[nv]);
    for (std::uint32_t t = 0; t < nt; ++t)
      if (usable[t])
        for (std::uint32_t v : m.triangles[t]) incident[fill[v]++] = t;
    std::sort(fan_links.begin(), fan_links.end());
    // Local union-find over the incident triangles of one vertex at a time.
    std::vector<std::uint32_t> parent;
    std::size_t li = 0;
    for (std::uint32_t v = 0; v < nv; ++v) {
      const std::uint32_t b = first[v], e = first[v + 1];
      if (e - b <= 1) {
        while (li < fan_links.size() && (fan_links[li].first >> 32) == v) ++li;
        continue;
      }
      parent.resize(e - b);
      std::iota(parent.begin(), parent.end(), 0u);
      auto slot = [&](std::uint32_t t) {
        const std::size_t k = static_cast<std::size_t>(
            std::lower_bound(incident.begin() + b, incident.begin() + e, t) - (incident.begin() + b));
        FREP_ASSERT(k < e - b, "fan link to a triangle not incident to the vertex");
        return static_cast<std::uint32_t>(k);
      };
      auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
      };
      std::size_t groups = e - b;
      while (li < fan_links.size() && (fan_links[li].first >> 32) == v) {
        std::size_t lj = li;
        while (lj < fan_links.size() && fan_links[lj].first == fan_links[li].first) ++lj;
        for (std::size_t k = li + 1; k < lj; ++k) {
          const std::uint32_t x = root(slot(fan_links[li].second)), y = root(slot(fan_links[k].second));
          if (x != y) parent[std::max(x, y)] = std::min(x, y), --groups;
        }
        li = lj;
      }
      if (groups > 1) {
        DefectLocation l = c.at_triangle(incident[b]);
        l.vertex = w.original_of_welded[v];
        l.point = c.unscale(m.vertices[v]);
        c.add(DefectKind::NonManifoldVertices, l);
      }
    }
  }

  const bool closed_manifold = c.d(DefectKind::OpenEdges).count == 0 && c.d(DefectKind::NonManifoldEdges).count == 0 &&
                               c.d(DefectKind::NonManifoldVertices).count == 0;
  if (closed_manifold && c.d(DefectKind::InconsistentOrientation).count == 0) {
    std::size_t used_vertices = 0;
    std::vector<char> used(nv, 0);
    std::size_t faces = 0;
    for (std::uint32_t t = 0; t < nt; ++t)
      if (usable[t]) {
        ++faces;
        for (std::uint32_t v : m.triangles[t]) used_vertices += !used[v], used[v] = 1;
      }
    const std::int64_t chi = std::int64_t(used_vertices) - std::int64_t(r.edges) + std::int64_t(faces);
    r.genus = (2 * std::int64_t(r.components) - chi) / 2;
    // Each shell must enclose volume; with several, their orientations and nesting are checked
    // below by winding numbers, once it is known that they do not cross.
    for (const Shell& s : shells)
      if (s.largest == kNone || !s.spatial || s.volume == 0) c.add(DefectKind::DegenerateShells, c.at_triangle(s.first));
    if (volume < 0) {
      DefectLocation l;
      if (shells.size() == 1) l = c.at_triangle(shells[0].first);
      else l.point = r.box.lo * 0.5 + r.box.hi * 0.5;
      c.add(DefectKind::InwardOrientation, l);
    }
  }

  // Self-intersections: candidate pairs from the BVH, classified exactly.
  if (opt.self_intersections && nt > 1) {
    r.self_intersections_checked = true;
    // Only triangles that can intersect anything go into the hierarchy.
    std::vector<std::uint32_t> live;
    for (std::uint32_t t = 0; t < nt; ++t)
      if (!flat[t]) live.push_back(t);
    TriMesh sub;
    if (live.size() < nt) {
      sub.vertices = m.vertices;
      for (std::uint32_t t : live) sub.triangles.push_back(m.triangles[t]);
    }
    const TriangleBvh bvh(live.size() < nt ? sub : m);
    const int threads = std::min(resolve_thread_count(opt.threads), 1024);
    // Per thread and kind of contact: a count, and the smallest (a, b) pairs seen so far in a
    // max-heap of at most max_examples, so memory does not grow with the number of pairs and
    // the examples do not depend on how pairs were spread over the threads.
    using Pair = std::uint64_t;  // a << 32 | b, a < b
    struct alignas(64) PerThread {
      std::uint64_t count[3] = {0, 0, 0};
      std::vector<Pair> best[3];
    };
    std::vector<PerThread> found(threads);
    const std::size_t keep = opt.max_examples;
    bvh.for_each_overlapping_pair_parallel(threads, [&](std::uint32_t a, std::uint32_t b, int th) {
      a = live[a], b = live[b];
      const Triangle &ta = m.triangles[a], &tb = m.triangles[b];
      const Vec3 p[3] = {m.vertices[ta[0]], m.vertices[ta[1]], m.vertices[ta[2]]};
      const Vec3 q[3] = {m.vertices[tb[0]], m.vertices[tb[1]], m.vertices[tb[2]]};
      const unsigned pi[3] = {ta[0], ta[1], ta[2]}, qi[3] = {tb[0], tb[1], tb[2]};
      const Contact k = classify_triangle_pair(p, pi, q, qi);
      if (k == Contact::None) return;
      const int slot = k == Contact::Cross ? 0 : (k == Contact::Overlap ? 1 : 2);
      PerThread& f = found[th];
      ++f.count[slot];
      if (keep == 0) return;
      const Pair key = (Pair(std::min(a, b)) << 32) | std::max(a, b);
      std::vector<Pair>& h = f.best[slot];
      if (h.size() < keep) {
        h.push_back(key);
        std::push_heap(h.begin(), h.end());
      } else if (key < h.front()) {
        std::pop_heap(h.begin(), h.end());
        h.back() = key;
        std::push_heap(h.begin(), h.end());
      }
    });
    const DefectKind kinds[3] = {DefectKind::SelfIntersections, DefectKind::Overlaps, DefectKind::TouchingPairs};
    for (int slot = 0; slot < 3; ++slot) {
      std::vector<Pair> all;
      Defect& d = c.d(kinds[slot]);
      for (PerThread& f : found) {
        d.count += f.count[slot];
        all.insert(all.end(), f.best[slot].begin(), f.best[slot].end());
      }
      std::sort(all.begin(), all.end());
      for (std::size_t i = 0; i < all.size() && d.examples.size() < keep; ++i) {
        DefectLocation l = c.at_triangle(std::uint32_t(all[i] >> 32));
        l.other = std::uint32_t(all[i]);
        d.examples.push_back(l);
      }
    }
  }
  // Several closed, consistently oriented shells that do not cross: just outside each shell's
  // largest triangle (on its normal's side) the winding number of the whole mesh must be 0. It
  // is -1 there for an inward shell that is not a cavity, and 2 - 1 = 1 for an outward shell
  // nested in another outward one (or a cavity inside a cavity).
  if (closed_manifold && c.d(DefectKind::InconsistentOrientation).count == 0 && shells.size() > 1 &&
      c.d(DefectKind::SelfIntersections).count == 0 && c.d(DefectKind::Overlaps).count == 0) {
    std::vector<std::pair<std::uint32_t, Vec3>> probes;  // (shell, point)
    for (std::uint32_t i = 0; i < shells.size(); ++i) {
      const Shell& s = shells[i];
      if (s.largest == kNone || !s.spatial) continue;
      const Vec3 a = m.corner(s.largest, 0), b = m.corner(s.largest, 1), cc = m.corner(s.largest, 2);
      const Vec3 n = cross(b - a, cc - a), g = (a + b + cc) / 3.0;
      // Offset from the centroid by a small fraction of the inradius (|n| / perimeter), doubled
      // until the point is strictly on the normal's side by the exact predicate.
      double delta = 1e-3 * length(n) / (length(b - a) + length(cc - b) + length(a - cc));
      const Vec3 u = n / length(n);
      for (int it = 0; it < 64; ++it, delta *= 2) {
        const Vec3 p = g + u * delta;
        if (exact::orient3d(a, b, cc, p) > 0) {
          probes.push_back({i, p});
          break;
        }
      }
    }
    // A closed shell's winding number is 0 outside its box, so only the shells whose boxes
    // contain a probe count: found through a hierarchy over the shell boxes (each box as a
    // "triangle" from its low to its high corner), then summed exactly over their triangles.
    // Disjoint shells cost about one pass over the mesh; if nesting makes the exact sums too
    // expensive, the whole mesh's hierarchical (far-field dipole) winding number is used.
    std::vector<std::uint32_t> shell_start(shells.size() + 1, 0), shell_tris;
    for (std::uint32_t t = 0; t < nt; ++t)
      if (!flat[t]) ++shell_start[shell_of[t] + 1];
    for (std::size_t i = 0; i < shells.size(); ++i) shell_start[i + 1] += shell_start[i];
    shell_tris.resize(shell_start.back());
    {
      std::vector<std::uint32_t> fill(shell_start.begin(), shell_start.end() - 1);
      for (std::uint32_t t = 0; t < nt; ++t)
        if (!flat[t]) shell_tris[fill[shell_of[t]]++] = t;
    }
    TriMesh box_mesh;
    for (std::uint32_t i = 0; i < shells.size(); ++i) {
      box_mesh.vertices.push_back(shells[i].box.lo);
      box_mesh.vertices.push_back(shells[i].box.hi);
      box_mesh.triangles.push_back({2 * i, 2 * i + 1, 2 * i});
    }
    const TriangleBvh box_bvh(box_mesh);
    auto inside = [](const Box3& b, const Vec3& p) {
      return b.lo.x <= p.x && p.x <= b.hi.x && b.lo.y <= p.y && p.y <= b.hi.y && b.lo.z <= p.z && p.z <= b.hi.z;
    };
    std::vector<std::vector<std::uint32_t>> around(probes.size());  // shells whose box holds the probe
    std::size_t work = 0;
    {
      const auto& nodes = box_bvh.nodes();
      std::vector<std::uint32_t> stack;
      for (std::size_t k = 0; k < probes.size(); ++k) {
        const Vec3& p = probes[k].second;
        stack.assign(1, 0);
        while (!stack.empty()) {
          const TriangleBvh::Node& n = nodes[stack.back()];
          stack.pop_back();
          if (!(n.lo[0] <= p.x && p.x <= n.hi[0] && n.lo[1] <= p.y && p.y <= n.hi[1] && n.lo[2] <= p.z &&
                p.z <= n.hi[2]))
            continue;
          if (!n.leaf()) {
            stack.push_back(n.index);
            stack.push_back(n.index + 1);
            continue;
          }
          for (std::uint32_t i = n.index; i < n.index + n.count; ++i) {
            const std::uint32_t j = box_bvh.order()[i];
            if (inside(shells[j].box, p)) around[k].push_back(j), work += shell_start[j + 1] - shell_start[j];
          }
        }
      }
    }
    std::vector<double> wn(probes.size(), 0.0);
    if (work <= (std::size_t(1) << 23)) {
      for (std::size_t k = 0; k < probes.size(); ++k) {
        double sum = 0;
        for (std::uint32_t j : around[k])
          for (std::uint32_t i = shell_start[j]; i < shell_start[j + 1]; ++i) {
            const std::uint32_t t = shell_tris[i];
            sum += solid_angle(probes[k].second, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
          }
        wn[k] = sum / (4 * 3.14159265358979323846);
      }
    } else {
      const MeshDistance md(m);
      for (std::size_t k = 0; k < probes.size(); ++k) wn[k] = md.winding_number(probes[k].second);
    }
    for (std::size_t k = 0; k < probes.size(); ++k)
      if (!(std::fabs(wn[k]) < 0.5)) c.add(DefectKind::ShellOrientation, c.at_triangle(shells[probes[k].first].largest));
  }

  r.area = std::ldexp(r.area, 2 * exponent);
  r.volume = std::ldexp(volume, 3 * exponent);
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
// Length of the well-formed UTF-8 sequence starting at s[i] (RFC 3629: no overlong forms, no
// surrogates, nothing beyond U+10FFFF), or 0 if there is none.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto at = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned b = at(i);
  std::size_t n;
  unsigned lo = 0x80, hi = 0xbf;  // allowed range of the second byte
  if (b >= 0xc2 && b <= 0xdf) n = 2;
  else if (b >= 0xe0 && b <= 0xef) n = 3, lo = b == 0xe0 ? 0xa0 : 0x80, hi = b == 0xed ? 0x9f : 0xbf;
  else if (b >= 0xf0 && b <= 0xf4) n = 4, lo = b == 0xf0 ? 0x90 : 0x80, hi = b == 0xf4 ? 0x8f : 0xbf;
  else return 0;
  if (at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
  return n;
}
// JSON string contents: quotes, backslashes and control characters escaped; well-formed UTF-8
// passes through; any other byte (a file name in Latin-1...) becomes the escape of U+00XX, its
// Latin-1 reading, so the output is always valid JSON.
std::string json_escape(const std::string& s) {
  std::string o;
  for (std::size_t i = 0; i < s.size();) {
    const char ch = s[i];
    const unsigned char u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      o += '\\', o += ch, ++i;
    } else if (u < 0x80) {
      if (u < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", u);
        o += buf;
      } else {
        o += ch;
      }
      ++i;
    } else if (const std::size_t n = utf8_length(s, i)) {
      o.append(s, i, n), i += n;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      o += buf, ++i;
    }
  }
  return o;
}
std::string json_num(double v) { return std::isfinite(v) ? fmt_g(v) : "null"; }
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
