// Flat regions merged (merge_flat.hpp): regions grown over edges between triangles in one plane,
// vertices inside them and on straight creases between two of them removed, and each region
// triangulated again from its outline with CGAL's constrained Delaunay triangulation.
#include "frep/mesh/merge_flat.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <vector>

#include "frep/mesh/bvh.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/tri_tri.hpp"

namespace frep {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, CGAL::Triangulation_face_base_with_info_2<int, K>>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<Vb, Fb>,
                                                       CGAL::No_constraint_intersection_tag>;

constexpr std::uint32_t kNone = MeshTopology::kNone;

struct Region {
  Vec3 normal_sum{0, 0, 0};  // sum of the triangles' cross products (twice their areas)
  Vec3 moment{0, 0, 0};      // sum of area times centroid
  double area = 0;
  bool flat = false;         // more than one triangle, every vertex within the tolerance of its plane
  Vec3 normal() const { return normal_sum / length(normal_sum); }
  Vec3 origin() const { return moment / area; }
  void add(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double ar = 0.5 * length(n);
    normal_sum = normal_sum + n;
    moment = moment + (a + b + c) * (ar / 3);
    area += ar;
  }
};

class FlatMerger {
 public:
  FlatMerger(const TriMesh& mesh, double tol) : m_(mesh), P_(mesh.vertices), T_(mesh.triangles), topo_(mesh), tol_(tol) {}

  TriMesh run(MergeFlatReport& rep) {
    grow_regions();
    std::vector<std::vector<Triangle>> made(regions_.size());
    std::vector<char> redone(regions_.size(), 0);
    std::vector<Triangle> out;
    // A region whose outline cannot be triangulated, or whose new triangles would meet another
    // part of the surface, keeps its triangles and pins its vertices; that changes its
    // neighbours' outlines, so the removals are decided again (rare).
    for (bool again = true; again;) {
      again = false;
      decide_removals();
      std::fill(redone.begin(), redone.end(), 0);
      for (std::uint32_t r = 0; r < regions_.size(); ++r) {
        if (!regions_[r].flat || !touches_removed(r)) continue;
        made[r].clear();
        if (triangulate(r, made[r])) {
          redone[r] = 1;
        } else {
          regions_[r].flat = false;
          ++rep.refused;
          again = true;
        }
      }
      if (again) continue;
      out = assemble(made, redone);
      std::vector<std::uint32_t> bad = meeting(made, redone);
      const std::vector<std::uint32_t> open = unpaired(out, made, redone);
      bad.insert(bad.end(), open.begin(), open.end());
      std::sort(bad.begin(), bad.end());
      bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
      for (std::uint32_t r : bad) {
        regions_[r].flat = false;
        ++rep.refused;
        again = true;
      }
    }
    return finish(rep, out, redone);
  }

 private:
  std::vector<Triangle> assemble(const std::vector<std::vector<Triangle>>& made, const std::vector<char>& redone) const {
    std::vector<Triangle> out;
    out.reserve(T_.size());
    for (std::uint32_t t = 0; t < T_.size(); ++t) {
      const std::uint32_t r = region_[t];
      if (!redone[r]) out.push_back(T_[t]);
      else if (members_[start_[r]] == t) out.insert(out.end(), made[r].begin(), made[r].end());
    }
    return out;
  }

  // The new triangles against every triangle near them, by the exact test of `frep check`: they
  // cover their region's points only to the tolerance, so where another part of the surface
  // comes that close, a region could now touch it. Returns the regions whose new triangles meet
  // another triangle.
  std::vector<std::uint32_t> meeting(const std::vector<std::vector<Triangle>>& made, const std::vector<char>& redone) const {
    TriMesh fresh;
    fresh.vertices = P_;
    std::vector<std::uint32_t> owner;
    for (std::uint32_t r = 0; r < regions_.size(); ++r)
      if (redone[r])
        for (const Triangle& tr : made[r]) fresh.triangles.push_back(tr), owner.push_back(r);
    std::vector<std::uint32_t> bad;
    if (fresh.triangles.empty()) return bad;
    const TriangleBvh bvh(fresh);
    // Each kept old triangle against the new ones, and each new one against those of other
    // regions: one region's new triangles are a triangulation of a polygon in its plane (exact
    // predicates in the plane), which cannot overlap, and near the plane what does not overlap
    // in it does not cross.
    auto check = [&](const Triangle& tr, std::uint32_t region) {
      const Vec3 p[3] = {P_[tr[0]], P_[tr[1]], P_[tr[2]]};
      const unsigned pi[3] = {tr[0], tr[1], tr[2]};
      Box3 box;
      for (const Vec3& x : p) box.add(x);
      const bool flat_tr = !(length2(cross(p[1] - p[0], p[2] - p[0])) > 0);
      bvh.for_each_meeting(box, [&](std::uint32_t j) {
        if (owner[j] == region) return;
        const Triangle& o = fresh.triangles[j];
        // The same corners in another order (the pair test calls that a duplicate, not a
        // contact): a hole filled with its own triangle turned over.
        if (same_corners(o, tr)) return bad.push_back(owner[j]);
        const Vec3 q[3] = {P_[o[0]], P_[o[1]], P_[o[2]]};
        if (!(length2(cross(q[1] - q[0], q[2] - q[0])) > 0)) return bad.push_back(owner[j]);  // a new one spans no plane
        if (flat_tr) return;  // an old one without area: the pair test needs a plane
        const unsigned qi[3] = {o[0], o[1], o[2]};
        if (classify_triangle_pair(p, pi, q, qi) != Contact::None) bad.push_back(owner[j]);
      });
    };
    for (std::uint32_t t = 0; t < T_.size(); ++t)
      if (!redone[region_[t]]) check(T_[t], kNone);
    for (std::size_t j = 0; j < fresh.triangles.size(); ++j) check(fresh.triangles[j], owner[j]);
    return bad;
  }

  static bool same_corners(Triangle a, Triangle b) {
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
  }

  // The regions with a new triangle's edge that is not run once each way by the triangles of
  // `out` (the surface must stay closed and consistently oriented around what changed). Only
  // edges at the new triangles' vertices are gathered.
  std::vector<std::uint32_t> unpaired(const std::vector<Triangle>& out, const std::vector<std::vector<Triangle>>& made,
                                      const std::vector<char>& redone) const {
    std::vector<std::array<std::uint32_t, 2>> owner(P_.size(), {kNone, kNone});  // per vertex: up to two regions of new triangles at it
    for (std::uint32_t r = 0; r < regions_.size(); ++r)
      if (redone[r])
        for (const Triangle& tr : made[r])
          for (std::uint32_t v : tr) {
            auto& o = owner[v];
            if (o[0] == kNone || o[0] == r) o[0] = r;
            else if (o[1] == kNone) o[1] = r;
          }
    std::vector<std::uint64_t> edges;  // directed, a << 32 | b
    std::vector<std::array<std::uint32_t, 3>> corners;  // (v, a, b) for each triangle (v, a, b) at a touched v
    for (const Triangle& tr : out)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = tr[static_cast<std::size_t>(k)], a = tr[static_cast<std::size_t>((k + 1) % 3)],
                            b = tr[static_cast<std::size_t>((k + 2) % 3)];
        if (owner[v][0] != kNone || owner[a][0] != kNone) edges.push_back(std::uint64_t(v) << 32 | a);
        if (owner[v][0] != kNone) corners.push_back({v, a, b});
      }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint32_t> bad;
    auto blame = [&](std::uint32_t v) {
      for (std::uint32_t r : owner[v])
        if (r != kNone) bad.push_back(r);
    };
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const std::uint32_t a = static_cast<std::uint32_t>(edges[i] >> 32), b = static_cast<std::uint32_t>(edges[i]);
      const bool twice = i + 1 < edges.size() && edges[i + 1] == edges[i];
      const bool back = std::binary_search(edges.begin(), edges.end(), std::uint64_t(b) << 32 | a);
      if (twice || !back) blame(a), blame(b);
    }
    // One fan per vertex: its triangles' far edges (a -> b) chain into a single cycle (two
    // fans sharing the vertex pass the edge test but pinch the surface there).
    std::sort(corners.begin(), corners.end());
    for (std::size_t i = 0; i < corners.size();) {
      std::size_t j = i;
      while (j < corners.size() && corners[j][0] == corners[i][0]) ++j;
      std::size_t steps = 0;
      std::uint32_t at = corners[i][1];
      do {
        const auto it = std::lower_bound(corners.begin() + static_cast<std::ptrdiff_t>(i), corners.begin() + static_cast<std::ptrdiff_t>(j),
                                         std::array<std::uint32_t, 3>{corners[i][0], at, 0});
        if (it == corners.begin() + static_cast<std::ptrdiff_t>(j) || (*it)[1] != at) break;
        at = (*it)[2];
      } while (++steps <= j - i && at != corners[i][1]);
      if (at != corners[i][1] || steps != j - i) blame(corners[i][0]);
      i = j;
    }
    return bad;
  }

  TriMesh finish(MergeFlatReport& rep, const std::vector<Triangle>& out, const std::vector<char>& redone) {
    for (std::uint32_t r = 0; r < regions_.size(); ++r) rep.regions += redone[r];
    for (char x : removed_) rep.removed += x != 0;
    TriMesh merged = compact_mesh(P_, out);
    merged.name = m_.name;
    return merged;
  }

 private:
  const TriMesh& m_;
  const std::vector<Vec3>& P_;
  const std::vector<Triangle>& T_;
  MeshTopology topo_;
  double tol_;
  std::vector<Region> regions_;
  std::vector<std::uint32_t> region_;         // per triangle
  std::vector<std::uint32_t> start_, members_;  // CSR: region -> its triangles, in order
  std::vector<char> removed_;                 // per vertex
  std::vector<std::uint32_t> next_, stamp_;   // per vertex, for one region's outline
  std::uint32_t cur_ = 0;

  std::uint32_t across(std::uint32_t t, std::uint32_t e) const {
    if (!topo_.manifold(e)) return kNone;
    const auto f = topo_.edge_faces(e);
    return f[0] == t ? f[1] : f[0];
  }

  // Regions grown breadth first from each triangle not yet in one, over manifold edges to
  // triangles facing the same way whose corners lie within half the tolerance of the plane
  // fitted so far (area-weighted normal through the centroid); then every region's vertices
  // are checked against its final plane with the whole tolerance.
  void grow_regions() {
    const std::size_t nt = T_.size();
    region_.assign(nt, kNone);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < nt; ++seed) {
      if (region_[seed] != kNone) continue;
      const std::uint32_t r = static_cast<std::uint32_t>(regions_.size());
      regions_.emplace_back();
      Region& g = regions_.back();
      region_[seed] = r;
      g.add(P_[T_[seed][0]], P_[T_[seed][1]], P_[T_[seed][2]]);
      if (!(g.area > 0)) continue;  // a degenerate seed spans no plane to grow in
      Vec3 n = g.normal(), c = g.origin();
      queue.assign({seed});
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::uint32_t t = queue[head];
        for (std::uint32_t e : topo_.triangle_edges(t)) {
          if (e == kNone) continue;
          const std::uint32_t o = across(t, e);
          if (o == kNone || region_[o] != kNone) continue;
          const Vec3& no = topo_.face_normal(o);
          if (length2(no) > 0 && !(dot(no, n) > 0.5)) continue;
          bool in = true;
          for (std::uint32_t v : T_[o]) in = in && std::fabs(dot(P_[v] - c, n)) <= 0.5 * tol_;
          if (!in) continue;
          region_[o] = r;
          g.add(P_[T_[o][0]], P_[T_[o][1]], P_[T_[o][2]]);
          n = g.normal(), c = g.origin();
          queue.push_back(o);
        }
      }
    }
    start_.assign(regions_.size() + 1, 0);
    for (std::uint32_t r : region_) ++start_[r + 1];
    for (std::size_t r = 0; r < regions_.size(); ++r) start_[r + 1] += start_[r];
    members_.resize(nt);
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::uint32_t t = 0; t < nt; ++t) members_[fill[region_[t]]++] = t;
    for (std::uint32_t r = 0; r < regions_.size(); ++r) {
      Region& g = regions_[r];
      if (start_[r + 1] - start_[r] < 2 || !(g.area > 0)) continue;
      const Vec3 n = g.normal(), c = g.origin();
      bool flat = std::isfinite(n.x) && std::isfinite(c.x);
      for (std::uint32_t i = start_[r]; flat && i < start_[r + 1]; ++i) {
        // Every triangle facing the final plane's way (one grown in at 60 degrees to an early
        // estimate could project turned over, and its hole would be filled).
        const Vec3& fn = topo_.face_normal(members_[i]);
        flat = !(length2(fn) > 0) || dot(fn, n) > 0.5;
        for (std::uint32_t v : T_[members_[i]]) flat = flat && std::fabs(dot(P_[v] - c, n)) <= tol_;
      }
      g.flat = flat;
    }
  }

  // The edges at v where two regions meet (the crease through v), into `out`; false if v has an
  // edge that is not manifold or touches more than two regions or a region that is not flat.
  bool crease_at(std::uint32_t v, std::uint32_t& r1, std::uint32_t& r2, std::vector<std::uint32_t>& out) const {
    out.clear();
    r1 = r2 = kNone;
    if (topo_.pinched(v)) return false;
    for (std::uint32_t t : topo_.vertex_faces(v)) {
      const std::uint32_t r = region_[t];
      if (!regions_[r].flat) return false;
      if (r1 == kNone || r1 == r) r1 = r;
      else if (r2 == kNone || r2 == r) r2 = r;
      else return false;
    }
    for (std::uint32_t t : topo_.vertex_faces(v))
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = topo_.triangle_edges(t)[static_cast<std::size_t>(k)];
        if (e == kNone) return false;
        const auto ev = topo_.edge_vertices(e);
        if (ev[0] != v && ev[1] != v) continue;
        const std::uint32_t o = across(t, e);
        if (o == kNone) return false;
        if (t < o && region_[o] != region_[t]) out.push_back(ev[0] == v ? ev[1] : ev[0]);
      }
    return true;
  }

  // Distance from p to the line through a and b, and whether p lies strictly between them.
  static bool between(const Vec3& p, const Vec3& a, const Vec3& b, double& dist) {
    const Vec3 d = b - a;
    const double l2 = length2(d);
    if (!(l2 > 0)) return false;
    const double s = dot(p - a, d) / l2;
    dist = length(p - (a + d * s));
    return s > 0 && s < 1;
  }

  // Which vertices go: those inside a flat region, and those on a straight crease between two
  // flat regions, kept where the crease bends by more than the tolerance (Douglas-Peucker over
  // each run of such vertices between two kept ones; a closed run keeps one).
  void decide_removals() {
    const std::size_t nv = P_.size();
    removed_.assign(nv, 0);
    std::vector<char> on_crease(nv, 0);
    std::vector<std::array<std::uint32_t, 2>> ends(nv, {kNone, kNone});
    std::vector<std::uint32_t> cr;
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (topo_.vertex_faces(v).empty()) continue;
      std::uint32_t r1, r2;
      if (!crease_at(v, r1, r2, cr)) continue;
      if (r2 == kNone) {
        removed_[v] = 1;  // inside one flat region
        continue;
      }
      double d = 0;
      if (cr.size() == 2 && between(P_[v], P_[cr[0]], P_[cr[1]], d) && d <= tol_) {
        on_crease[v] = 1;
        removed_[v] = 1;
        ends[v] = {cr[0], cr[1]};
      }
    }
    // The crease relation is symmetric (an edge between two regions), so a run is a path or a loop.
    auto other = [&](std::uint32_t x, std::uint32_t from) { return ends[x][0] == from ? ends[x][1] : ends[x][0]; };
    std::vector<char> seen(nv, 0);
    std::vector<std::uint32_t> run;
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (!on_crease[v] || seen[v]) continue;
      // One end: walk from v until a vertex off the crease, or back to v (a loop: v is kept).
      std::uint32_t prev = v, x = ends[v][0];
      for (std::size_t steps = 0; on_crease[x] && x != v && steps <= nv; ++steps) {
        const std::uint32_t nx = other(x, prev);
        prev = x, x = nx;
      }
      std::uint32_t p = x, c = prev;
      if (x == v) {
        removed_[v] = 0;
        c = ends[v][0];  // round the loop from v
      }
      run.assign({x});
      while (c != x && on_crease[c] && run.size() <= nv) {
        seen[c] = 1;
        run.push_back(c);
        const std::uint32_t nc = other(c, p);
        p = c, c = nc;
      }
      seen[v] = 1;
      run.push_back(c);
      keep_bends(run, 0, run.size() - 1);
      if (run.front() == run.back()) keep_three(run);
    }
  }

  // Douglas-Peucker over run[i..j], whose ends are kept: the vertices between go unless one is
  // farther than the tolerance from the line of the ends, or not between them; then the worst
  // stays and both halves are looked at again.
  void keep_bends(const std::vector<std::uint32_t>& run, std::size_t i, std::size_t j) {
    if (j <= i + 1) return;
    std::size_t worst = i;
    double bad = tol_;
    for (std::size_t k = i + 1; k < j; ++k) {
      double d = 0;
      const bool in = run[i] != run[j] && between(P_[run[k]], P_[run[i]], P_[run[j]], d);
      const double b = in ? d : INFINITY;
      if (b > bad) bad = b, worst = k;
    }
    if (worst == i) return;
    if (bad == INFINITY) {  // not between (or a loop's two ends): keep the one farthest from the first end
      double far = -1;
      for (std::size_t k = i + 1; k < j; ++k)
        if (const double d = length2(P_[run[k]] - P_[run[i]]); d > far) far = d, worst = k;
    }
    removed_[run[worst]] = 0;
    keep_bends(run, i, worst);
    keep_bends(run, worst, j);
  }

  // A loop keeps at least three vertices (two would make the two regions' outlines one edge run
  // both ways, which cannot be triangulated): the one farthest from the line of the kept ones.
  void keep_three(const std::vector<std::uint32_t>& loop) {
    std::vector<std::uint32_t> kept;
    for (std::size_t k = 0; k + 1 < loop.size(); ++k)
      if (!removed_[loop[k]]) kept.push_back(loop[k]);
    while (kept.size() < 3 && kept.size() + 1 < loop.size()) {
      std::size_t best = 0;
      double far = -1;
      for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
        if (!removed_[loop[k]]) continue;
        double d = length(P_[loop[k]] - P_[kept[0]]);
        if (kept.size() == 2) between(P_[loop[k]], P_[kept[0]], P_[kept[1]], d);
        if (d > far) far = d, best = k;
      }
      if (far < 0) break;
      removed_[loop[best]] = 0;
      kept.push_back(loop[best]);
    }
  }

  bool touches_removed(std::uint32_t r) const {
    for (std::uint32_t i = start_[r]; i < start_[r + 1]; ++i)
      for (std::uint32_t v : T_[members_[i]])
        if (removed_[v]) return true;
    return false;
  }

  // Region r triangulated from its outline's kept vertices, into `out`; false where that fails
  // (crossing or touching outline edges in the plane, two vertices at one point, an area that
  // does not match): the region then stays as it is.
  bool triangulate(std::uint32_t r, std::vector<Triangle>& out) {
    ++cur_;
    if (next_.size() < P_.size()) next_.assign(P_.size(), kNone), stamp_.assign(P_.size(), 0), local_.resize(P_.size());
    const Region& g = regions_[r];
    const Vec3 n = g.normal(), c = g.origin();
    const Vec3 axis = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z) ? Vec3{1, 0, 0}
                      : std::fabs(n.y) <= std::fabs(n.z)                                   ? Vec3{0, 1, 0}
                                                                                           : Vec3{0, 0, 1};
    const Vec3 u = cross(n, axis) / length(cross(n, axis)), w = cross(n, u);
    auto flat2 = [&](std::uint32_t v) { return K::Point_2(dot(P_[v] - c, u), dot(P_[v] - c, w)); };
    // The outline: edges of the region's triangles whose other triangle is not in it, as the
    // triangles run them; at a removed vertex exactly one leaves it.
    std::vector<std::array<std::uint32_t, 2>> outline;
    double perimeter = 0, old_area = 0;
    for (std::uint32_t i = start_[r]; i < start_[r + 1]; ++i) {
      const std::uint32_t t = members_[i];
      const Triangle& tr = T_[t];
      const K::Point_2 a = flat2(tr[0]), b = flat2(tr[1]), d = flat2(tr[2]);
      old_area += 0.5 * ((b.x() - a.x()) * (d.y() - a.y()) - (b.y() - a.y()) * (d.x() - a.x()));
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = topo_.triangle_edges(t)[static_cast<std::size_t>(k)];
        const std::uint32_t o = e == kNone ? kNone : across(t, e);
        if (o != kNone && region_[o] == r) continue;
        const std::uint32_t va = tr[static_cast<std::size_t>(k)], vb = tr[static_cast<std::size_t>((k + 1) % 3)];
        outline.push_back({va, vb});
        perimeter += length(P_[vb] - P_[va]);
        if (removed_[va]) {
          if (stamp_[va] == cur_) return false;
          stamp_[va] = cur_;
          next_[va] = vb;
        }
      }
    }
    // Kept vertices: points of the triangulation.
    Cdt cdt;
    std::uint32_t kept = 0;
    for (std::uint32_t i = start_[r]; i < start_[r + 1]; ++i)
      for (std::uint32_t v : T_[members_[i]]) {
        if (removed_[v] || stamp_[v] == cur_) continue;
        stamp_[v] = cur_;
        local_[v] = cdt.insert(flat2(v));
        local_[v]->info() = v;
        ++kept;
      }
    if (cdt.number_of_vertices() != kept) return false;  // two vertices at one point of the plane
    std::vector<std::array<std::uint32_t, 2>> segments;
    for (const auto& [a, b0] : outline) {
      if (removed_[a]) continue;
      std::uint32_t b = b0;
      for (std::size_t steps = 0; removed_[b]; ++steps) {
        if (stamp_[b] != cur_ || steps > outline.size()) return false;
        b = next_[b];
      }
      if (a == b) return false;
      segments.push_back({a, b});
    }
    try {
      for (const auto& [a, b] : segments) cdt.insert_constraint(local_[a], local_[b]);
    } catch (const std::exception&) {
      return false;  // outline edges crossing in the plane
    }
    for (const auto& [a, b] : segments)
      if (!cdt.is_edge(local_[a], local_[b])) return false;  // split by a vertex on it
    if (cdt.dimension() != 2) return false;
    // Inside: faces behind an odd number of outline edges from the infinite face.
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
    std::vector<Cdt::Edge> border;
    std::vector<Cdt::Face_handle> stack;
    auto flood = [&](Cdt::Face_handle start, int level) {
      stack.assign({start});
      while (!stack.empty()) {
        const Cdt::Face_handle f = stack.back();
        stack.pop_back();
        if (f->info() != -1) continue;
        f->info() = level;
        for (int i = 0; i < 3; ++i) {
          const Cdt::Face_handle nb = f->neighbor(i);
          if (nb->info() != -1) continue;
          if (cdt.is_constrained(Cdt::Edge(f, i))) border.emplace_back(f, i);
          else stack.push_back(nb);
        }
      }
    };
    flood(cdt.infinite_face(), 0);
    while (!border.empty()) {
      const Cdt::Edge e = border.back();
      border.pop_back();
      const Cdt::Face_handle nb = e.first->neighbor(e.second);
      if (nb->info() == -1) flood(nb, e.first->info() + 1);
    }
    double new_area = 0;
    std::uint32_t used = 0;
    ++cur_;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (f->info() % 2 != 1) continue;
      const K::Point_2 &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &d = f->vertex(2)->point();
      new_area += 0.5 * ((b.x() - a.x()) * (d.y() - a.y()) - (b.y() - a.y()) * (d.x() - a.x()));
      Triangle tr;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = f->vertex(k)->info();
        tr[static_cast<std::size_t>(k)] = v;
        if (stamp_[v] != cur_) stamp_[v] = cur_, ++used;
      }
      out.push_back(tr);
    }
    // Same area (up to the creases straightened, each by at most the tolerance), and every kept
    // vertex still in use.
    return used == kept && std::fabs(new_area - old_area) <= 2 * tol_ * perimeter + 1e-9 * old_area;
  }

  std::vector<Cdt::Vertex_handle> local_;  // per vertex: its point in the current triangulation
};

}  // namespace

TriMesh merge_flat_regions(const TriMesh& mesh, double tolerance, MergeFlatReport* report) {
  MergeFlatReport rep;
  TriMesh out = mesh.triangles.empty() ? mesh : FlatMerger(mesh, tolerance).run(rep);
  if (report) *report = rep;
  return out;
}

}  // namespace frep
