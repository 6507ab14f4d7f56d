// The arrangement of crossing triangles, on CGAL's exact kernel (Epeck): intersections of
// triangle pairs are computed exactly, each cut triangle (or group of overlapping coplanar
// triangles) is triangulated in its plane with the intersections as constraints, and points
// on an edge are given to every triangle along that edge so that no T-junction is left.
#include "mesh/arrangement.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "frep/error.hpp"
#include "util/union_find.hpp"

namespace frep::arrangement {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using P3 = K::Point_3;
using P2 = K::Point_2;
using T3 = K::Triangle_3;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<
    K,
    CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<K>,
                                         CGAL::Constrained_triangulation_face_base_2<K>>,
    CGAL::Exact_intersections_tag>;

struct Less3 {
  bool operator()(const P3& a, const P3& b) const { return CGAL::compare_xyz(a, b) == CGAL::SMALLER; }
};
struct Less2 {
  bool operator()(const P2& a, const P2& b) const { return CGAL::compare_xy(a, b) == CGAL::SMALLER; }
};

// What cuts one triangle: points (vertex ids) and segments between them.
struct Cuts {
  std::vector<std::uint32_t> points;
  std::vector<std::array<std::uint32_t, 2>> segments;
};

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(a) << 32) | b;
}

class Arranger {
 public:
  Arranger(const TriMesh& mesh, const MeshTopology& topo, const TriangleBvh& bvh, const std::function<void()>& poll)
      : m_(mesh), topo_(topo), bvh_(bvh), poll_(poll), group_(mesh.triangles.size()) {}

  Arrangement run(const std::vector<std::uint32_t>& seeds) {
    for (std::uint32_t t : seeds) involve(t);
    // Intersections spread the cut to the triangles they meet; points on edges spread it to the
    // triangles along those edges. Both until nothing new is involved.
    for (;;) {
      while (!work_.empty()) {
        const std::uint32_t t = work_.back();
        work_.pop_back();
        intersect_with_neighbours(t);
      }
      if (!spread_edge_points()) break;
    }
    return assemble();
  }

 private:
  const TriMesh& m_;
  const MeshTopology& topo_;
  const TriangleBvh& bvh_;
  const std::function<void()>& poll_;
  std::unordered_map<std::uint32_t, Cuts> cuts_;  // the involved triangles
  std::vector<std::uint32_t> work_;
  std::unordered_set<std::uint64_t> pairs_done_;
  std::unordered_set<std::uint64_t> has_point_;        // (triangle, point) already in its cuts
  std::unordered_map<std::uint32_t, std::size_t> edge_checked_;  // per triangle: cuts points tested for edges
  UnionFind group_;                                    // coplanar overlapping triangles
  std::map<P3, std::uint32_t, Less3> ids_;             // every point met so far
  std::vector<P3> new_points_;                         // ids from m_.vertices.size() on
  std::size_t polls_ = 0;

  P3 vertex(std::uint32_t v) const {
    if (v < m_.vertices.size()) return P3(m_.vertices[v].x, m_.vertices[v].y, m_.vertices[v].z);
    return new_points_[v - m_.vertices.size()];
  }
  T3 triangle(std::uint32_t t) const {
    const Triangle& f = m_.triangles[t];
    return T3(vertex(f[0]), vertex(f[1]), vertex(f[2]));
  }
  std::uint32_t id_of(const P3& p) {
    auto [it, fresh] = ids_.try_emplace(p, 0);
    if (fresh) {
      it->second = static_cast<std::uint32_t>(m_.vertices.size() + new_points_.size());
      new_points_.push_back(p);
    }
    return it->second;
  }
  void register_vertices(std::uint32_t t) {
    for (std::uint32_t v : m_.triangles[t]) ids_.try_emplace(vertex(v), v);
  }
  void involve(std::uint32_t t) {
    if (cuts_.count(t)) return;
    cuts_[t];
    register_vertices(t);
    work_.push_back(t);
  }
  void add_point(std::uint32_t t, std::uint32_t p) {
    if (has_point_.insert((std::uint64_t(t) << 32) | p).second) cuts_[t].points.push_back(p);
  }
  void poll() {
    if (++polls_ % 256 == 0 && poll_) poll_();
  }

  void intersect_with_neighbours(std::uint32_t a) {
    const Triangle& fa = m_.triangles[a];
    Box3 box;
    for (std::uint32_t v : fa) box.add(m_.vertices[v]);
    std::vector<std::uint32_t> near;
    bvh_.for_each_meeting(box, [&](std::uint32_t t) {
      if (t != a) near.push_back(t);
    });
    const T3 ta = triangle(a);
    for (std::uint32_t b : near) {
      if (!pairs_done_.insert(pair_key(a, b)).second) continue;
      poll();
      const T3 tb = triangle(b);
      if (!CGAL::do_intersect(ta, tb)) continue;
      const auto result = CGAL::intersection(ta, tb);
      if (!result) continue;
      register_vertices(b);
      // The result's corners, and its edges (a polygon's in order around it).
      std::vector<P3> corners;
      bool flat = false;  // two-dimensional: the triangles overlap in their common plane
      if (const P3* p = boost::get<P3>(&*result)) {
        corners = {*p};
      } else if (const K::Segment_3* s = boost::get<K::Segment_3>(&*result)) {
        corners = {s->source(), s->target()};
      } else if (const T3* t = boost::get<T3>(&*result)) {
        corners = {t->vertex(0), t->vertex(1), t->vertex(2)};
        flat = true;
      } else if (const auto* poly = boost::get<std::vector<P3>>(&*result)) {
        corners = *poly;
        flat = true;
      }
      std::vector<std::uint32_t> ids;
      ids.reserve(corners.size());
      for (const P3& p : corners) ids.push_back(id_of(p));
      // Meeting only in shared vertices, or along their shared edge, cuts nothing.
      const Triangle& fb = m_.triangles[b];
      const auto shared = [&](std::uint32_t v) {
        return (v == fa[0] || v == fa[1] || v == fa[2]) && (v == fb[0] || v == fb[1] || v == fb[2]);
      };
      bool trivial = !flat;
      for (std::uint32_t v : ids) trivial = trivial && shared(v);
      if (trivial) continue;
      if (flat) group_.unite(a, b);
      for (std::uint32_t t : {a, b}) {
        involve(t);
        for (std::uint32_t v : ids) add_point(t, v);
        if (ids.size() == 2 && ids[0] != ids[1]) cuts_[t].segments.push_back({ids[0], ids[1]});
        if (ids.size() >= 3)
          for (std::size_t k = 0; k < ids.size(); ++k) cuts_[t].segments.push_back({ids[k], ids[(k + 1) % ids.size()]});
      }
    }
  }

  // Points strictly inside an edge of an involved triangle go to every triangle along that edge.
  // True if that involved a triangle not involved before.
  bool spread_edge_points() {
    bool grew = false;
    std::vector<std::uint32_t> involved;
    involved.reserve(cuts_.size());
    for (const auto& [t, c] : cuts_) involved.push_back(t);
    for (std::uint32_t t : involved) {
      std::size_t& from = edge_checked_[t];
      const Triangle f = m_.triangles[t];
      const P3 c[3] = {vertex(f[0]), vertex(f[1]), vertex(f[2])};
      while (from < cuts_[t].points.size()) {
        const std::uint32_t v = cuts_[t].points[from++];
        if (v == f[0] || v == f[1] || v == f[2]) continue;
        const P3 p = vertex(v);
        for (int k = 0; k < 3; ++k) {
          const P3 &a = c[k], &b = c[(k + 1) % 3];
          if (!CGAL::collinear(a, b, p) || !CGAL::collinear_are_strictly_ordered_along_line(a, p, b)) continue;
          const std::uint32_t e = topo_.triangle_edges(t)[k];
          if (e == MeshTopology::kNone) continue;
          for (std::uint32_t g : topo_.edge_faces(e)) {
            if (g == t) continue;
            if (!cuts_.count(g)) grew = true;
            involve(g);
            add_point(g, v);
          }
        }
      }
    }
    return grew || !work_.empty();
  }

  // Triangulates each group of involved triangles in its plane and keeps the faces that lie in
  // at least one of them, with their multiplicity; other triangles are kept whole.
  Arrangement assemble() {
    Arrangement out;
    std::map<std::uint32_t, std::vector<std::uint32_t>> groups;
    for (const auto& [t, c] : cuts_) groups[group_.find(t)].push_back(t);
    out.cut_triangles = cuts_.size();
    std::vector<char> cut(m_.triangles.size(), 0);
    for (const auto& [t, c] : cuts_) cut[t] = 1;
    for (std::uint32_t t = 0; t < m_.triangles.size(); ++t)
      if (!cut[t]) out.pieces.push_back({m_.triangles[t], 1, t});
    for (auto& [root, members] : groups) {
      std::sort(members.begin(), members.end());
      if (members.size() > 1) ++out.coplanar_groups;
      triangulate_group(members, out.pieces);
    }
    out.vertices = m_.vertices;
    out.new_vertices = new_points_.size();
    for (const P3& p : new_points_) {
      const Vec3 r{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
      if (K::FT(r.x) != p.x() || K::FT(r.y) != p.y() || K::FT(r.z) != p.z()) ++out.rounded_vertices;
      out.vertices.push_back(r);
    }
    return out;
  }

  void triangulate_group(const std::vector<std::uint32_t>& members, std::vector<Piece>& pieces) {
    poll();
    // Project along the largest component of the plane's normal, keeping (x, y, z) cyclic so
    // that counter-clockwise in the projection means a normal along +axis.
    const T3 first = triangle(members[0]);
    const K::Vector_3 n = CGAL::normal(first.vertex(0), first.vertex(1), first.vertex(2));
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (CGAL::compare(CGAL::abs(n[k]), CGAL::abs(n[axis])) == CGAL::LARGER) axis = k;
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    const auto project = [&](const P3& p) { return P2(p[u], p[w]); };

    // Points first, all at once (CGAL sorts them spatially and walks from the last one: one by
    // one, locating each from scratch dominated large coplanar groups), then the constraints
    // between their vertex handles.
    Cdt cdt;
    std::map<P2, std::uint32_t, Less2> id2;
    std::vector<P2> points;
    const auto add = [&](std::uint32_t v) {
      const P2 q = project(vertex(v));
      if (id2.emplace(q, v).second) points.push_back(q);
    };
    std::vector<std::array<P2, 3>> shapes;
    std::vector<int> signs;
    std::vector<std::array<std::uint32_t, 2>> constraints;
    for (std::uint32_t t : members) {
      const Triangle& f = m_.triangles[t];
      for (std::uint32_t v : f) add(v);
      const Cuts& c = cuts_.at(t);
      for (std::uint32_t v : c.points) add(v);
      std::array<P2, 3> s = {project(vertex(f[0])), project(vertex(f[1])), project(vertex(f[2]))};
      shapes.push_back(s);
      signs.push_back(CGAL::orientation(s[0], s[1], s[2]) == CGAL::LEFT_TURN ? 1 : -1);
      for (int k = 0; k < 3; ++k) constraints.push_back({f[k], f[(k + 1) % 3]});
      for (const auto& seg : c.segments) constraints.push_back(seg);
    }
    cdt.insert(points.begin(), points.end());
    std::map<P2, Cdt::Vertex_handle, Less2> handle;
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) handle.emplace(v->point(), v);
    poll();
    for (const auto& c : constraints) {
      const Cdt::Vertex_handle a = handle.at(project(vertex(c[0]))), b = handle.at(project(vertex(c[1])));
      if (a != b) cdt.insert_constraint(a, b);
    }
    poll();
    // A point made where constraints cross lies in the plane: its dropped coordinate from the
    // plane's equation.
    const P3 origin = first.vertex(0);
    const auto lift = [&](const P2& q) {
      K::FT c[3];
      c[u] = q.x();
      c[w] = q.y();
      c[axis] = origin[axis] - (n[u] * (q.x() - origin[u]) + n[w] * (q.y() - origin[w])) / n[axis];
      return P3(c[0], c[1], c[2]);
    };
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      std::array<std::uint32_t, 3> v;
      P2 q[3];
      for (int k = 0; k < 3; ++k) {
        q[k] = f->vertex(k)->point();
        auto it = id2.find(q[k]);
        if (it == id2.end()) it = id2.emplace(q[k], id_of(lift(q[k]))).first;
        v[k] = it->second;
      }
      const P2 centre = CGAL::centroid(q[0], q[1], q[2]);
      int multiplicity = 0;
      std::uint32_t source = members[0];
      bool inside_any = false;
      for (std::size_t i = 0; i < members.size(); ++i) {
        const auto& s = shapes[i];
        const CGAL::Orientation want = signs[i] > 0 ? CGAL::LEFT_TURN : CGAL::RIGHT_TURN;
        if (CGAL::orientation(s[0], s[1], centre) == want && CGAL::orientation(s[1], s[2], centre) == want &&
            CGAL::orientation(s[2], s[0], centre) == want) {
          multiplicity += signs[i];
          if (!inside_any) source = members[i];
          inside_any = true;
        }
      }
      // Faces outside every member fill the hull; faces covered as often each way are no surface.
      if (multiplicity != 0) pieces.push_back({v, multiplicity, source});
    }
  }
};

}  // namespace

Arrangement arrange(const TriMesh& mesh, const MeshTopology& topology, const TriangleBvh& bvh,
                    const std::vector<std::uint32_t>& seeds, const std::function<void()>& poll) {
  try {
    Arranger a(mesh, topology, bvh, poll);
    return a.run(seeds);
  } catch (const CGAL::Failure_exception& e) {
    throw InputError(mesh.name, 0, std::string("the exact arrangement of the crossing triangles failed (CGAL: ") +
                                       e.what() + ")");
  }
}

}  // namespace frep::arrangement
