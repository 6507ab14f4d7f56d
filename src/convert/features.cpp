// Feature extraction for the converter: flat regions by union-find over flat edges, each split
// into convex polygons greedily (Hertel-Mehlhorn: drop an internal edge when both its ends stay
// convex, longest first), crease edges, and the vertices that need their own term.
#include "convert/features.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"

namespace frep::convert_detail {
namespace {

constexpr std::uint32_t kNone = MeshTopology::kNone;

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Orientation of three vertices of a flat region in the coordinate plane that drops the normal's
// largest axis; exact (dropping a coordinate is exact), and positive for a counter-clockwise turn
// about the outward normal.
struct Plane2 {
  int u, v;   // kept axes
  int flip;   // +1 or -1
  Plane2(const Vec3& n) {
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    const int k = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    u = (k + 1) % 3;
    v = (k + 2) % 3;
    flip = n[k] >= 0 ? 1 : -1;
  }
  int orient(const Vec3& a, const Vec3& b, const Vec3& c) const {
    return flip * exact::orient2d(a[u], a[v], b[u], b[v], c[u], c[v]);
  }
  // Whether a polygon turns left at b (prev a, next c) or goes straight on. Straight back (a
  // and c on the same side of b) is not convex: it would make a zero-width spike.
  bool convex(const Vec3& a, const Vec3& b, const Vec3& c) const {
    const int o = orient(a, b, c);
    if (o != 0) return o > 0;
    return (b[u] - a[u]) * (c[u] - b[u]) + (b[v] - a[v]) * (c[v] - b[v]) > 0;
  }
};

// Creases whose normals are closer than this (cosine) take their cluster's sign.
constexpr double kClusterCos = 0.1;
// Signs are trusted on a cone's ray only with this margin (cosine).
constexpr double kSignMargin = 0.02;

// Whether three points lie on one line, exactly.
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return exact::orient2d(a.x, a.y, b.x, b.y, c.x, c.y) == 0 && exact::orient2d(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
         exact::orient2d(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
}

// Extreme rays of the cone {u : u . d <= 0 for all d in dirs} (unit vectors): intersections of
// two of its facet planes that satisfy every constraint. Empty when the cone is just {0}.
void voronoi_rays(const std::vector<Vec3>& dirs, std::vector<Vec3>& rays) {
  rays.clear();
  const std::size_t k = dirs.size();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j) {
      Vec3 r = cross(dirs[i], dirs[j]);
      const double len = length(r);
      if (!(len > 1e-12)) continue;
      r = r / len;
      for (const Vec3 cand : {r, -r}) {
        bool inside = true;
        for (const Vec3& d : dirs)
          if (dot(cand, d) > 1e-9) {
            inside = false;
            break;
          }
        if (!inside) continue;
        bool dup = false;
        for (const Vec3& q : rays) dup |= dot(q, cand) > 1 - 1e-12;
        if (!dup) rays.push_back(cand);
      }
    }
}

// Whether the sign of u . sign_normal is that of u . pseudonormal, clearly, on every ray.
bool signs_agree(const std::vector<Vec3>& rays, const Vec3& sign_normal, const Vec3& pseudonormal) {
  const double ls = length(sign_normal), lp = length(pseudonormal);
  if (!(ls > 0) || !(lp > 0)) return false;
  for (const Vec3& r : rays) {
    const double a = dot(r, sign_normal) / ls, b = dot(r, pseudonormal) / lp;
    // Where even the vertex's own sign is faint (a sliver), only its own term is to be trusted.
    if (a * b <= 0 || std::fabs(a) < kSignMargin || std::fabs(b) < kSignMargin) return false;
  }
  return true;
}

// Greedy convex merging of a region's triangles.
void split_convex(const TriMesh& m, const MeshTopology& topo, const std::vector<EdgeShape>& shape,
                  const std::vector<std::uint32_t>& tris,
                  const Vec3& normal, Region& region) {
  const Plane2 plane(normal);
  // Polygons start as the triangles; `owner` maps a triangle to its polygon (union-find).
  const std::size_t n = tris.size();
  std::vector<Polygon> polys(n);
  std::vector<std::uint32_t> owner(n);
  std::iota(owner.begin(), owner.end(), 0u);
  std::vector<std::uint32_t> local(0);
  // Triangle id -> index in `tris` (tris is sorted).
  auto index_of = [&](std::uint32_t t) {
    return static_cast<std::uint32_t>(std::lower_bound(tris.begin(), tris.end(), t) - tris.begin());
  };
  struct Internal {
    double length2;
    std::uint32_t a, b;  // endpoints (a -> b in the first triangle)
    std::uint32_t t0, t1;
  };
  std::vector<Internal> internal;
  for (std::size_t i = 0; i < n; ++i) {
    const Triangle& t = m.triangles[tris[i]];
    polys[i].loop = {t[0], t[1], t[2]};
    polys[i].internal.assign(3, 0);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = topo.triangle_edges(tris[i])[k];
      if (shape[e] != EdgeShape::Flat) continue;
      polys[i].internal[k] = 1;
      const auto faces = topo.edge_faces(e);
      const std::uint32_t other = faces[0] == tris[i] ? faces[1] : faces[0];
      if (other > tris[i]) internal.push_back({length2(m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]]), t[k],
                                               t[(k + 1) % 3], tris[i], other});
    }
  }
  std::sort(internal.begin(), internal.end(), [](const Internal& x, const Internal& y) {
    return x.length2 != y.length2 ? x.length2 > y.length2 : (x.t0 != y.t0 ? x.t0 < y.t0 : x.t1 < y.t1);
  });
  auto position = [](const Polygon& p, std::uint32_t from, std::uint32_t to) -> std::size_t {
    const std::size_t k = p.loop.size();
    for (std::size_t i = 0; i < k; ++i)
      if (p.loop[i] == from && p.loop[(i + 1) % k] == to) return i;
    return k;
  };
  for (const Internal& e : internal) {
    const std::uint32_t pa = find(owner, index_of(e.t0)), pb = find(owner, index_of(e.t1));
    if (pa == pb) continue;  // already one polygon (cannot happen for a convex one, but be safe)
    Polygon& A = polys[pa];
    Polygon& B = polys[pb];
    std::size_t ia = position(A, e.a, e.b), ib = position(B, e.b, e.a);
    FREP_ASSERT(ia < A.loop.size() && ib < B.loop.size(), "internal edge missing from its polygons");
    const std::size_t na = A.loop.size(), nb = B.loop.size();
    // The whole boundary A and B share around this edge: a chain of edges A runs along one way
    // and B the other. Extend it backward (A's previous edge is B's next) and forward.
    std::size_t len = 1;  // shared edges, from A.loop[ia] to A.loop[ia + len]
    while (len < na && len < nb && A.loop[(ia + na - 1) % na] == B.loop[(ib + len + 1) % nb]) {
      ia = (ia + na - 1) % na;
      ++len;
    }
    while (len < na && len < nb && A.loop[(ia + len + 1) % na] == B.loop[(ib + nb - 1) % nb]) {
      ib = (ib + nb - 1) % nb;
      ++len;
    }
    if (len >= na || len >= nb) continue;  // one polygon inside the other: leave them
    // Chain from s = A.loop[ia] to t = A.loop[ia + len]; in B it runs from t (at ib) to s.
    const std::uint32_t s_id = A.loop[ia], t_id = A.loop[(ia + len) % na];
    const Vec3& vs = m.vertices[s_id];
    const Vec3& vt = m.vertices[t_id];
    const Vec3& s_prev = m.vertices[A.loop[(ia + na - 1) % na]];  // before s in A
    const Vec3& s_next = m.vertices[B.loop[(ib + len + 1) % nb]];  // after s in B
    const Vec3& t_prev = m.vertices[B.loop[(ib + nb - 1) % nb]];   // before t in B
    const Vec3& t_next = m.vertices[A.loop[(ia + len + 1) % na]];  // after t in A
    if (!plane.convex(s_prev, vs, s_next) || !plane.convex(t_prev, vt, t_next)) continue;
    // Merged loop: A from t around to s, then B from s around to t; the chain's inner vertices
    // end up inside the merged polygon.
    Polygon merged;
    for (std::size_t k = len; k < na; ++k) {
      merged.loop.push_back(A.loop[(ia + k) % na]);
      merged.internal.push_back(A.internal[(ia + k) % na]);
    }
    for (std::size_t k = len; k < nb; ++k) {
      merged.loop.push_back(B.loop[(ib + k) % nb]);
      merged.internal.push_back(B.internal[(ib + k) % nb]);
    }
    A = std::move(merged);
    B = Polygon{};
    owner[pb] = pa;
  }
  // Vertices where a polygon goes straight on add nothing to its prism test: drop them (the
  // merged side is internal, with the margin, if either part was).
  for (std::size_t i = 0; i < n; ++i) {
    if (owner[i] != i) continue;
    Polygon& p = polys[i];
    for (bool changed = true; changed && p.loop.size() > 3;) {
      changed = false;
      for (std::size_t k = 0; k < p.loop.size() && p.loop.size() > 3; ++k) {
        const std::size_t prev = (k + p.loop.size() - 1) % p.loop.size(), next = (k + 1) % p.loop.size();
        if (plane.orient(m.vertices[p.loop[prev]], m.vertices[p.loop[k]], m.vertices[p.loop[next]]) != 0) continue;
        p.internal[prev] = p.internal[prev] || p.internal[k];
        p.loop.erase(p.loop.begin() + static_cast<std::ptrdiff_t>(k));
        p.internal.erase(p.internal.begin() + static_cast<std::ptrdiff_t>(k));
        changed = true;
        break;
      }
    }
    region.polygons.push_back(std::move(p));
  }
}

}  // namespace

Features extract_features(const TriMesh& m, const MeshTopology& topo) {
  const std::vector<EdgeShape> shape = edge_shapes(m, topo);
  Features f;
  const std::size_t nt = m.triangles.size(), nv = m.vertices.size();
  // Regions: triangles joined through flat edges.
  std::vector<std::uint32_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e)
    if (shape[e] == EdgeShape::Flat) {
      const auto faces = topo.edge_faces(e);
      const std::uint32_t a = find(parent, faces[0]), b = find(parent, faces[1]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  f.region_of.assign(nt, kNone);
  std::vector<std::vector<std::uint32_t>> members;
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (!topo.usable(t)) continue;
    const std::uint32_t r = find(parent, t);
    if (r == t) {
      f.region_of[t] = static_cast<std::uint32_t>(members.size());
      members.emplace_back();
    } else {
      f.region_of[t] = f.region_of[r];
    }
    members[f.region_of[t]].push_back(t);
  }
  f.regions.resize(members.size());
  for (std::size_t r = 0; r < members.size(); ++r) {
    Region& reg = f.regions[r];
    // The plane of the region's largest triangle (all are exactly coplanar).
    std::uint32_t best = members[r][0];
    double best_area = -1, area = 0;
    Vec3 weighted;
    for (std::uint32_t t : members[r]) {
      const Vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
      const double ar = 0.5 * length(cross(b - a, c - a));
      if (ar > best_area) best_area = ar, best = t;
      weighted += (a + b + c) * (ar / 3.0);
      area += ar;
    }
    reg.normal = topo.face_normal(best);
    reg.center = area > 0 ? weighted / area : m.corner(best, 0);
    // Anchor: the region's vertex nearest its centroid keeps the plane's rounding small.
    reg.anchor = m.triangles[best][0];
    double near = INFINITY;
    for (std::uint32_t t : members[r])
      for (std::uint32_t v : m.triangles[t])
        if (const double d2 = length2(m.vertices[v] - reg.center); d2 < near) near = d2, reg.anchor = v;
    reg.triangles = members[r].size();
    split_convex(m, topo, shape, members[r], reg.normal, reg);
  }

  // Crease edges, with runs of collinear creases between the same two regions merged into one
  // segment (a box edge cut into pieces by its faces' triangulation is still one edge). A gentle
  // crease (normals less than ~84 degrees apart) joins a region's cluster: its Voronoi region is
  // the wedge between the two normals, on which both planes have the surface's sign with margin
  // n1 . n2.
  struct Crease {
    std::uint32_t a, b, ra, rb;
  };
  std::vector<Crease> creases;
  std::vector<std::vector<std::uint32_t>> creases_at(nv);
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    const EdgeShape s = shape[e];
    if (s == EdgeShape::Flat) continue;
    FREP_ASSERT(s == EdgeShape::Convex || s == EdgeShape::Concave, "converter given an edge that is not a solid's");
    const auto faces = topo.edge_faces(e);
    const auto ends = topo.edge_vertices(e);
    creases_at[ends[0]].push_back(static_cast<std::uint32_t>(creases.size()));
    creases_at[ends[1]].push_back(static_cast<std::uint32_t>(creases.size()));
    creases.push_back({ends[0], ends[1], f.region_of[faces[0]], f.region_of[faces[1]]});
  }
  auto same_regions = [](const Crease& x, const Crease& y) {
    return (x.ra == y.ra && x.rb == y.rb) || (x.ra == y.rb && x.rb == y.ra);
  };
  // The crease continuing c through its end v, if v joins exactly two creases, of the same two
  // regions, in a straight line.
  auto continuation = [&](std::uint32_t c, std::uint32_t v) -> std::uint32_t {
    if (creases_at[v].size() != 2) return kNone;
    const std::uint32_t d = creases_at[v][0] == c ? creases_at[v][1] : creases_at[v][0];
    if (d == c || !same_regions(creases[c], creases[d])) return kNone;
    const std::uint32_t u = creases[c].a == v ? creases[c].b : creases[c].a;
    const std::uint32_t w = creases[d].a == v ? creases[d].b : creases[d].a;
    return collinear(m.vertices[u], m.vertices[v], m.vertices[w]) ? d : kNone;
  };
  std::vector<std::uint8_t> used(creases.size(), 0);
  for (std::uint32_t c = 0; c < creases.size(); ++c) {
    if (used[c]) continue;
    used[c] = 1;
    std::uint32_t ends[2] = {creases[c].a, creases[c].b};
    for (int side = 0; side < 2; ++side) {
      std::uint32_t cur = c;
      for (std::uint32_t next; (next = continuation(cur, ends[side])) != kNone && !used[next];) {
        used[next] = 1;
        ends[side] = creases[next].a == ends[side] ? creases[next].b : creases[next].a;
        cur = next;
      }
    }
    const std::uint32_t ra = creases[c].ra, rb = creases[c].rb;
    const bool gentle = dot(f.regions[ra].normal, f.regions[rb].normal) > kClusterCos;
    f.edges.push_back({ends[0], ends[1], ra, rb, gentle ? ra : kNone, false});
  }

  // Vertex terms. At a vertex, every crease edge's clamped distance equals the vertex distance,
  // so which edge wins there is arbitrary: each must carry the right sign on the vertex's
  // Voronoi region, or the vertex gets a term of its own that wins those ties. That region lies
  // in the cone V = {u : u . e <= 0 for every edge direction e at the vertex} (empty for a
  // saddle); signs are linear in u, so checking V's extreme rays suffices. On V, outside is
  // where u . N > 0 for the vertex's angle-weighted pseudonormal N (Baerentzen and Aanaes).
  std::vector<std::vector<std::uint32_t>> edges_at(nv);
  for (std::uint32_t i = 0; i < f.edges.size(); ++i) {
    edges_at[f.edges[i].a].push_back(i);
    edges_at[f.edges[i].b].push_back(i);
  }
  std::vector<std::uint8_t> is_term(nv, 0);
  std::vector<Vec3> dirs, rays;
  std::vector<std::uint32_t> seen;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (edges_at[v].empty()) continue;
    const Vec3& pv = m.vertices[v];
    dirs.clear();
    seen.clear();
    for (std::uint32_t t : topo.vertex_faces(v))
      for (std::uint32_t w : m.triangles[t])
        if (w != v && std::find(seen.begin(), seen.end(), w) == seen.end()) {
          seen.push_back(w);
          const Vec3 d = m.vertices[w] - pv;
          dirs.push_back(d / length(d));
        }
    voronoi_rays(dirs, rays);
    if (rays.empty()) continue;  // no point off the surface has this vertex as its nearest
    const Vec3 nv_ = topo.vertex_pseudonormal(v);
    bool ok = true;
    for (std::uint32_t i : edges_at[v]) {
      const EdgeTerm& e = f.edges[i];
      const Vec3 sign_normal = e.cluster != kNone ? f.regions[e.cluster].normal
                                                  : f.regions[e.region_a].normal + f.regions[e.region_b].normal;
      if (!signs_agree(rays, sign_normal, nv_)) {
        ok = false;
        break;
      }
    }
    if (!ok) {
      f.vertices.push_back({v, nv_});
      is_term[v] = 1;
    }
  }
  // Edge orientation: computed from a vertex-term end, so the tie there is exact.
  for (EdgeTerm& e : f.edges) {
    if (is_term[e.a] && is_term[e.b]) e.interpolate = true;
    else if (is_term[e.b]) std::swap(e.a, e.b), std::swap(e.region_a, e.region_b);
  }
  return f;
}

}  // namespace frep::convert_detail
