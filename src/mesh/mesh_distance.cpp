// The signed-distance oracle: the 4-wide query hierarchy and its build, the pseudonormal sign
// (normals from mesh/topology.hpp), the batch queries.
#include "frep/mesh/mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "frep/error.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/util/thread_pool.hpp"
#include "mesh/mesh_simd.hpp"

namespace frep {

struct MeshDistance::Data {
  struct Tri {
    Vec3 a, b, c;
  };
  std::vector<mesh_detail::WideNode> wide;        // the query hierarchy
  std::vector<mesh_detail::WideDipoles> dipoles;  // per wide node
  std::vector<mesh_detail::TriPacket> packets;
  std::vector<Tri> tri;                       // in BVH leaf order
  std::vector<std::uint32_t> tri_id;          // leaf order -> mesh triangle index
  std::vector<Vec3> face_normal;              // per mesh triangle, unit (zero if degenerate)
  std::vector<Vec3> edge_normal;              // per topology edge
  std::vector<std::array<std::uint32_t, 3>> tri_edges;  // per mesh triangle: edge k's id, or kNone
  std::vector<Vec3> vertex_normal;            // per welded vertex
  std::vector<Triangle> welded;               // per mesh triangle, welded vertex indices
  std::vector<std::uint32_t> leaf_of;         // mesh triangle index -> leaf order (closest_point_on)
  Box3 box;                                   // of the triangles' corners
};

namespace {

constexpr double kFourPi = 4 * 3.14159265358979323846;
// Points per parallel work item: enough to amortize handing it out, small enough to balance.
constexpr std::size_t kQueryGrain = 1024;

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5), with the
// feature it lies on. Degenerate triangles fall back to their edges; an edge region is only
// taken for an edge of non-zero length (the denominator is its squared length: a triangle with
// two corners at one point used to give 0 / 0 there, a NaN distance).
Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = dot(ab, ab);
  double t = l2 > 0 ? dot(p - a, ab) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return a + ab * t;
}

inline Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Feature& f) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return f = Feature::Vertex0, a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return f = Feature::Vertex1, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
    const double v = d1 / (d1 - d3);
    return f = Feature::Edge0, a + ab * v;
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return f = Feature::Vertex2, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) {
    const double w = d2 / (d2 - d6);
    return f = Feature::Edge2, a + ac * w;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0 && (d4 - d3) + (d5 - d6) > 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return f = Feature::Edge1, b + (c - b) * w;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (collinear corners): the closest point is on one of the edges.
    const Vec3 q0 = closest_on_segment(p, a, b), q1 = closest_on_segment(p, b, c), q2 = closest_on_segment(p, c, a);
    const double e0 = length2(p - q0), e1 = length2(p - q1), e2 = length2(p - q2);
    if (e0 <= e1 && e0 <= e2) return f = Feature::Edge0, q0;
    if (e1 <= e2) return f = Feature::Edge1, q1;
    return f = Feature::Edge2, q2;
  }
  const double denom = 1.0 / sum;
  const double v = vb * denom, w = vc * denom;
  return f = Feature::Face, a + ab * v + ac * w;
}

// Winding-number data of a binary node: the triangles below act, from far away, as one dipole.
struct Dipole {
  Vec3 area_normal;  // sum of the triangles' area vectors (half the cross products)
  Vec3 center;       // area-weighted centroid
  double radius;     // distance from center to the farthest corner below the node
};

std::vector<Dipole> binary_dipoles(const std::vector<TriangleBvh::Node>& nodes,
                                   const std::vector<std::array<Vec3, 3>>& corners) {
  // Children before parents (children have larger indices).
  std::vector<Dipole> dip(nodes.size(), Dipole{});
  std::vector<double> node_area(nodes.size(), 0);
  for (std::size_t ni = nodes.size(); ni-- > 0;) {
    const TriangleBvh::Node& n = nodes[ni];
    Dipole& wn = dip[ni];
    Vec3 weighted;
    double area = 0;
    if (n.leaf()) {
      for (std::uint32_t i = n.index; i < n.index + n.count; ++i) {
        const auto& [ta, tb, tc] = corners[i];
        const Vec3 an = cross(tb - ta, tc - ta) * 0.5;
        const double a = length(an);
        wn.area_normal += an;
        weighted += (ta + tb + tc) * (a / 3.0);
        area += a;
      }
    } else {
      for (std::uint32_t ch : {n.index, n.index + 1}) {
        wn.area_normal += dip[ch].area_normal;
        weighted += dip[ch].center * node_area[ch];
        area += node_area[ch];
      }
    }
    node_area[ni] = area;
    wn.center = area > 0 ? weighted / area : Vec3{(n.lo[0] + n.hi[0]) * 0.5, (n.lo[1] + n.hi[1]) * 0.5,
                                                  (n.lo[2] + n.hi[2]) * 0.5};
    // Radius: farthest box corner bounds the farthest triangle corner.
    double r2 = 0;
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner{(k & 1) ? n.hi[0] : n.lo[0], (k & 2) ? n.hi[1] : n.lo[1], (k & 4) ? n.hi[2] : n.lo[2]};
      r2 = std::max(r2, length2(corner - wn.center));
    }
    wn.radius = std::sqrt(r2);
  }
  return dip;
}

// The 4-wide query hierarchy: each wide node takes the children of a binary node and keeps
// opening its largest inner child (by surface area) until it has four. Leaves become packets of
// four triangles (leaf order), the last lane repeated as padding.
struct WideBuilder {
  const std::vector<TriangleBvh::Node>& bin;
  const std::vector<std::array<Vec3, 3>>& corners;  // per triangle, leaf order
  const std::vector<Dipole>& dipole;                 // per binary node
  double beta2;                                      // squared far-field ratio
  std::vector<mesh_detail::WideNode>& wide;
  std::vector<mesh_detail::WideDipoles>& dipoles;
  std::vector<mesh_detail::TriPacket>& packets;

  static double area(const TriangleBvh::Node& n) {
    const double x = n.hi[0] - n.lo[0], y = n.hi[1] - n.lo[1], z = n.hi[2] - n.lo[2];
    return x * y + y * z + z * x;
  }

  std::int32_t leaf(const TriangleBvh::Node& n) {
    const auto first = static_cast<std::int32_t>(packets.size());
    for (std::uint32_t base = 0; base < n.count; base += mesh_detail::kWidth) {
      mesh_detail::TriPacket& p = packets.emplace_back();
      for (int j = 0; j < mesh_detail::kWidth; ++j) {
        const std::uint32_t i = n.index + std::min<std::uint32_t>(base + j, n.count - 1);
        const auto& [a, b, c] = corners[i];
        const Vec3 nn = cross(b - a, c - a), e[3] = {b - a, c - b, a - c};
        const double n2 = length2(nn);
        for (int k = 0; k < 3; ++k) {
          p.a[k][j] = a[k], p.b[k][j] = b[k], p.c[k][j] = c[k];
          p.n[k][j] = n2 > 0 ? nn[k] : 0;
          p.inv_e2[k][j] = length2(e[k]) > 0 ? 1 / length2(e[k]) : 0;
        }
        p.inv_n2[j] = n2 > 0 ? 1 / n2 : 0;
        p.tri[j] = i;
        p.real[j] = base + j < n.count ? 1 : 0;
      }
    }
    return ~first;
  }

  // Builds the wide node over binary node `root`'s children (or over `root` alone if a leaf).
  std::uint32_t node(std::uint32_t root) {
    std::vector<std::uint32_t> kids;
    if (bin[root].leaf()) kids = {root};
    else kids = {bin[root].index, bin[root].index + 1};
    while (kids.size() < std::size_t(mesh_detail::kWidth)) {
      int open = -1;
      for (std::size_t k = 0; k < kids.size(); ++k)
        if (!bin[kids[k]].leaf() && (open < 0 || area(bin[kids[k]]) > area(bin[kids[open]]))) open = int(k);
      if (open < 0) break;
      const std::uint32_t c = bin[kids[open]].index;
      kids[open] = c;
      kids.push_back(c + 1);
    }
    const auto w = static_cast<std::uint32_t>(wide.size());
    wide.emplace_back();
    dipoles.emplace_back();
    for (int j = 0; j < mesh_detail::kWidth; ++j) {
      std::int32_t child = 0;  // an empty slot: child 0 (the root, never a child) without packets
      std::uint32_t count = 0;
      double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      Dipole dip{{}, {}, INFINITY};
      if (j < int(kids.size())) {
        const TriangleBvh::Node& n = bin[kids[j]];
        dip = dipole[kids[j]];
        for (int k = 0; k < 3; ++k) lo[k] = n.lo[k], hi[k] = n.hi[k];
        if (n.leaf()) {
          child = leaf(n);
          count = static_cast<std::uint32_t>(packets.size()) - ~child;
        } else {
          child = static_cast<std::int32_t>(node(kids[j]));
        }
      }
      mesh_detail::WideNode& wn = wide[w];  // after the recursion: `wide` may have grown
      for (int k = 0; k < 3; ++k) wn.lo[k][j] = lo[k], wn.hi[k][j] = hi[k];
      wn.child[j] = child;
      wn.packets[j] = count;
      mesh_detail::WideDipoles& wd = dipoles[w];
      for (int k = 0; k < 3; ++k) wd.center[k][j] = dip.center[k], wd.area_normal[k][j] = dip.area_normal[k];
      wd.far2[j] = beta2 * dip.radius * dip.radius;
    }
    return w;
  }
};

// Squared distances and the winding number's triple products must neither overflow nor
// underflow in double precision: refuse scales where they would, rather than answer wrongly.
void check_range(const TriMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError(mesh.name, 0, "mesh has no triangles");
  double extent = 0, largest = 0;
  Vec3 lo = mesh.vertices.empty() ? Vec3{} : mesh.vertices[0], hi = lo;
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) {
      const Vec3& q = mesh.vertices[v];
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], q[c]);
        hi[c] = std::max(hi[c], q[c]);
        largest = std::max(largest, std::fabs(q[c]));
      }
    }
  for (int c = 0; c < 3; ++c) extent = std::max(extent, hi[c] - lo[c]);
  if (largest > 1e100 || (extent > 0 && extent < 1e-90))
    throw InputError(mesh.name, 0,
                     "coordinates out of the range the distance oracle handles exactly (|x| <= 1e100, size >= "
                     "1e-90): rescale the mesh");
}

}  // namespace

MeshDistance::MeshDistance(const TriMesh& mesh, const MeshDistanceOptions& options) {
  mesh.check_consistent();
  check_range(mesh);
  const WeldResult w = weld(mesh, {options.weld_tolerance});
  *this = MeshDistance(w.mesh, MeshTopology(w.mesh), options);
}

MeshDistance::MeshDistance(const TriMesh& m, const MeshTopology& topo, const MeshDistanceOptions& options,
                           const TriangleBvh* bvh)
    : d_(std::make_unique<Data>()) {
  m.check_consistent();
  check_range(m);
  FREP_ASSERT(topo.num_triangles() == m.triangles.size() && topo.num_vertices() == m.vertices.size(),
              "topology of another mesh");
  Data& d = *d_;
  const std::size_t nt = m.triangles.size();
  d.welded = m.triangles;
  std::optional<TriangleBvh> own;
  if (!bvh) {
    BvhOptions bo;
    bo.max_leaf_size = options.max_leaf_size;
    bvh = &own.emplace(m, bo);
  }
  FREP_ASSERT(bvh->order().size() == nt, "hierarchy of another mesh");
  d.tri_id = bvh->order();
  d.tri.resize(nt);
  d.leaf_of.resize(nt);
  for (std::size_t i = 0; i < nt; ++i) d.leaf_of[d.tri_id[i]] = static_cast<std::uint32_t>(i);
  std::vector<std::array<Vec3, 3>> corners(nt);
  for (std::size_t i = 0; i < nt; ++i) {
    const std::uint32_t t = d.tri_id[i];
    corners[i] = {m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)};
    d.tri[i] = {corners[i][0], corners[i][1], corners[i][2]};
    for (const Vec3& v : corners[i]) d.box.add(v);
  }
  const double beta2 = options.winding_beta * options.winding_beta;
  WideBuilder{bvh->nodes(), corners, binary_dipoles(bvh->nodes(), corners), beta2, d.wide, d.dipoles, d.packets}.node(0);

  // Pseudonormals from the topology. A collapsed triangle has no edges of its own there: its
  // edges take the normal of the topology's edge between the same vertices, if there is one.
  d.face_normal = topo.face_normals();
  d.vertex_normal = topo.vertex_pseudonormals();
  d.edge_normal.resize(topo.num_edges());
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) d.edge_normal[e] = topo.edge_pseudonormal(e);
  d.tri_edges.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) {
    d.tri_edges[t] = topo.triangle_edges(t);
    if (!topo.usable(t))
      for (int k = 0; k < 3; ++k) d.tri_edges[t][k] = topo.find_edge(m.triangles[t][k], m.triangles[t][(k + 1) % 3]);
  }
}

MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;
MeshDistance::~MeshDistance() = default;

std::size_t MeshDistance::num_triangles() const { return d_->tri.size(); }

std::optional<MeshDistance::RayHit> MeshDistance::first_hit(const Vec3& o, const Vec3& dir, double t_max) const {
  if (!std::isfinite(o.x + o.y + o.z + dir.x + dir.y + dir.z) || !(t_max >= 0)) return std::nullopt;
  double t = t_max;
  const std::uint32_t i = mesh_detail::first_hit(d_->wide.data(), d_->packets.data(), o, dir, t);
  if (i >= d_->tri.size()) return std::nullopt;
  return RayHit{t, d_->tri_id[i]};
}

namespace {
// Queries whose squared distances stay finite (meshes are limited to 1e100, check_range).
// Beyond, including infinities and NaN, every answer is NaN: the searches would compare
// infinities and NaNs and could not end.
bool query_in_range(const Vec3& p) {
  return std::fabs(p.x) <= kMaxQueryCoordinate && std::fabs(p.y) <= kMaxQueryCoordinate &&
         std::fabs(p.z) <= kMaxQueryCoordinate;
}
}  // namespace

ClosestPoint MeshDistance::closest_point(const Vec3& p) const {
  if (!query_in_range(p)) return {NAN, p, 0, Feature::Face};
  // The SIMD search finds the nearest triangle; its closest point and feature come from the
  // scalar region test (the pseudonormal sign needs the feature).
  double d2 = INFINITY;
  const std::uint32_t i = mesh_detail::nearest_triangle(d_->wide.data(), d_->packets.data(), p, d2);
  if (i >= d_->tri.size()) return {NAN, p, 0, Feature::Face};  // a NaN coordinate: nothing is nearer than infinity
  return closest_point_on(p, d_->tri_id[i]);
}

ClosestPoint MeshDistance::closest_point(const Vec3& p, std::uint32_t& hint) const {
  if (!query_in_range(p)) return {NAN, p, 0, Feature::Face};
  if (hint < d_->welded.size()) {
    // The hint's squared distance bounds the search; with room for the SIMD search computing it
    // another way (relative rounding, and cancellation next to the surface). A bound too small
    // finds nothing and the search starts over; any bound above the answer finds the same
    // triangle (ties go to the smallest index).
    const Data::Tri& t = d_->tri[d_->leaf_of[hint]];
    Feature f;
    const Vec3 q = closest_on_triangle(p, t.a, t.b, t.c, f);
    double d2 = length2(p - q) * (1 + 0x1p-30) + 0x1p-44 * (length2(p) + length2(t.a));
    const std::uint32_t i = mesh_detail::nearest_triangle(d_->wide.data(), d_->packets.data(), p, d2);
    if (i < d_->tri.size()) {
      hint = d_->tri_id[i];
      return closest_point_on(p, hint);
    }
  }
  const ClosestPoint c = closest_point(p);
  if (!std::isnan(c.distance)) hint = c.triangle;
  return c;
}

ClosestPoint MeshDistance::closest_point_on(const Vec3& p, std::uint32_t triangle) const {
  FREP_ASSERT(triangle < d_->welded.size(), "triangle index out of range");
  Feature f;
  const Data::Tri& t = d_->tri[d_->leaf_of[triangle]];
  const Vec3 q = closest_on_triangle(p, t.a, t.b, t.c, f);
  // Inside the face's prism the distance is the plane distance: computed from the normal it
  // does not inherit the rounding of the in-plane coordinates of q, which matters for huge
  // triangles (a face 1e38 wide would otherwise be off by about 1e22).
  if (f == Feature::Face) {
    const Vec3& n = d_->face_normal[triangle];
    if (length2(n) > 0) return {std::fabs(dot(p - t.a, n)), q, triangle, f};
  }
  return {length(p - q), q, triangle, f};
}

double MeshDistance::winding_number(const Vec3& p) const {
  if (!query_in_range(p)) return NAN;
  return mesh_detail::solid_angle_sum(d_->wide.data(), d_->dipoles.data(), d_->packets.data(), p) / kFourPi;
}

double MeshDistance::winding_number_exact(const Vec3& p) const {
  double s = 0;
  for (const Data::Tri& t : d_->tri) s += solid_angle(p, t.a, t.b, t.c);
  return s / kFourPi;
}

int MeshDistance::pseudonormal_sign(const Vec3& p, const ClosestPoint& c) const {
  const double s = dot(p - c.point, pseudonormal(c));
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

Vec3 MeshDistance::pseudonormal(const ClosestPoint& c) const {
  const Triangle& t = d_->welded[c.triangle];
  auto edge_normal = [&](int k) {
    const std::uint32_t e = d_->tri_edges[c.triangle][k];
    return e == MeshTopology::kNone ? Vec3{} : d_->edge_normal[e];
  };
  Vec3 n;
  switch (c.feature) {
    case Feature::Face: n = d_->face_normal[c.triangle]; break;
    case Feature::Edge0: n = edge_normal(0); break;
    case Feature::Edge1: n = edge_normal(1); break;
    case Feature::Edge2: n = edge_normal(2); break;
    case Feature::Vertex0: n = d_->vertex_normal[t[0]]; break;
    case Feature::Vertex1: n = d_->vertex_normal[t[1]]; break;
    case Feature::Vertex2: n = d_->vertex_normal[t[2]]; break;
  }
  return n;
}

double MeshDistance::signed_distance(const Vec3& p, SignMethod method) const {
  std::uint32_t hint = kNoHint;
  return signed_distance(p, method, hint);
}

double MeshDistance::signed_distance(const Vec3& p, SignMethod method, std::uint32_t& hint) const {
  const ClosestPoint c = closest_point(p, hint);
  return c.distance == 0 || std::isnan(c.distance) ? c.distance : side(p, c, method) * c.distance;
}

int MeshDistance::side(const Vec3& p, const ClosestPoint& c, SignMethod method) const {
  if (method == SignMethod::Pseudonormal) {
    // Outside the triangles' box is outside the solid. Far away, the rounded distances of many
    // triangles tie, and the one kept need not hold the closest feature its sign relies on.
    if (!d_->box.contains(p)) return 1;
    const int s = pseudonormal_sign(p, c);
    if (s != 0) return s;
    // Degenerate feature (zero normal): fall back on the winding number.
  }
  return winding_number(p) > 0.5 ? -1 : 1;
}

void MeshDistance::signed_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                                   SignMethod method, int threads) const {
  parallel_for_ranges(threads, n, kQueryGrain, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) out[i] = signed_distance(Vec3{x[i], y[i], z[i]}, method);
  });
}

void MeshDistance::unsigned_distance(const double* x, const double* y, const double* z, double* out, std::size_t n,
                                     int threads) const {
  parallel_for_ranges(threads, n, kQueryGrain, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) out[i] = closest_point(Vec3{x[i], y[i], z[i]}).distance;
  });
}

std::vector<double> signed_distance(const TriMesh& mesh, const std::vector<double>& x, const std::vector<double>& y,
                                    const std::vector<double>& z, SignMethod method) {
  FREP_ASSERT(x.size() == y.size() && y.size() == z.size(), "point columns differ in length");
  const MeshDistance md(mesh);
  std::vector<double> out(x.size());
  md.signed_distance(x.data(), y.data(), z.data(), out.data(), x.size(), method);
  return out;
}

}  // namespace frep
