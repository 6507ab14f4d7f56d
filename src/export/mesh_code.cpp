// Mesh oracles in the C and GLSL exports as data plus a loop (see mesh_code.hpp).
#include "export/mesh_code.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "export/export_util.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/topology.hpp"

namespace frep::export_detail {
namespace {

// Triangles per hierarchy leaf: 8 keeps the hierarchy (6 floats and 2 ints per node) at about a
// fifth of the data, and a walk still tests only a few leaves.
constexpr int kLeafSize = 8;

constexpr std::uint32_t kNone = 0xffffffffu;

// Replaces every "{P}" in `text` by `prefix` and "{D}" by `depth`.
std::string fill(std::string_view text, const std::string& prefix, std::uint32_t depth = 0) {
  std::string out;
  out.reserve(text.size() + 64);
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '{' && i + 2 < text.size() && text[i + 2] == '}' && (text[i + 1] == 'P' || text[i + 1] == 'D')) {
      out += text[i + 1] == 'P' ? prefix : std::to_string(depth);
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

// Comma-separated items wrapped at about 100 columns, indented by two spaces; no trailing comma
// (GLSL's array constructors refuse one).
class ArrayWriter {
 public:
  explicit ArrayWriter(std::ostream& out) : out_(out) {}
  void item(std::string_view s) {
    if (col_ == 0) {
      out_ << "  ";
      col_ = 2;
    } else if (col_ + s.size() + 2 > 100) {
      out_ << ",\n  ";
      col_ = 2;
    } else {
      out_ << ", ";
      col_ += 2;
    }
    out_ << s;
    col_ += s.size();
  }
  void end() { out_ << (col_ ? "\n" : ""); }

 private:
  std::ostream& out_;
  std::size_t col_ = 0;
};

// The shortest text that reads back as exactly `v`, as a C double literal (finite values only).
std::string c_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";  // "1e+20" stays; "3" becomes "3.0"
  return s;
}

std::string c_float(float v) {
  if (std::isinf(v)) return v < 0 ? "-INFINITY" : "INFINITY";
  std::string s = shortest_float(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

// GLSL has no literal for infinity (box corners of meshes beyond float range are refused before).
std::string glsl_float(float v) {
  std::string s = shortest_float(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string thousands(std::size_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

// Appends one mesh to the tables.
void add_mesh(MeshTables& t, const MeshOracle& oracle) {
  const MeshField& field = oracle.field();
  // MeshOracle refuses what convert refuses: a closed, manifold, consistently oriented solid
  // without zero-area triangles, whose sign is the pseudonormal's. The neighbours below and the
  // sign in the generated code rely on it.
  FREP_ASSERT(field.solid() && field.sign() == SignMethod::Pseudonormal, "a mesh oracle that is not a valid solid");
  const TriMesh& w = field.welded();
  const MeshTopology& topo = field.topology();
  BvhOptions bo;
  bo.max_leaf_size = kLeafSize;
  const TriangleBvh bvh(w, bo);
  const std::vector<std::uint32_t>& order = bvh.order();
  const std::size_t nt = w.triangles.size();
  FREP_ASSERT(order.size() == nt && !bvh.empty(), "hierarchy of another mesh");

  MeshTables::Mesh m;
  m.oracle = &oracle;
  m.root = static_cast<std::uint32_t>(t.nodes.size());
  m.first_triangle = static_cast<std::uint32_t>(t.triangles.size());
  m.triangles = static_cast<std::uint32_t>(nt);
  // Triangles in leaf order, so that a leaf is a run; vertices numbered as the triangles first
  // use them (unused ones are left out).
  std::vector<std::uint32_t> position(nt), vertex(w.vertices.size(), kNone);
  for (std::size_t i = 0; i < nt; ++i) position[order[i]] = m.first_triangle + static_cast<std::uint32_t>(i);
  const auto first_vertex = static_cast<std::uint32_t>(t.vertices.size());
  for (std::uint32_t tri : order) {
    std::array<std::uint32_t, 3> corners{}, across{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = w.triangles[tri][k];
      if (vertex[v] == kNone) {
        vertex[v] = static_cast<std::uint32_t>(t.vertices.size());
        t.vertices.push_back(w.vertices[v]);
        t.vertex_normals.push_back(topo.vertex_pseudonormal(v));
      }
      corners[k] = vertex[v];
      const std::uint32_t e = topo.triangle_edges(tri)[k];
      FREP_ASSERT(e != MeshTopology::kNone && topo.edge_face_count(e) == 2, "an open or non-manifold edge in a solid");
      const auto faces = topo.edge_faces(e);
      across[k] = position[faces[0] == tri ? faces[1] : faces[0]];
    }
    t.triangles.push_back(corners);
    t.neighbours.push_back(across);
  }
  m.vertices = static_cast<std::uint32_t>(t.vertices.size()) - first_vertex;
  // The hierarchy, with global indices, and its depth (children come after their parents).
  const std::vector<TriangleBvh::Node>& nodes = bvh.nodes();
  std::vector<std::uint32_t> depth(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const TriangleBvh::Node& n = nodes[i];
    MeshTables::Node out;
    for (int k = 0; k < 3; ++k) out.lo[k] = n.lo[k], out.hi[k] = n.hi[k];
    out.count = n.count;
    out.first = n.index + (n.leaf() ? m.first_triangle : m.root);
    if (!n.leaf()) {
      FREP_ASSERT(n.index > i && n.index + 1 < nodes.size(), "hierarchy children before their parent");
      depth[n.index] = depth[n.index + 1] = depth[i] + 1;
    }
    t.depth = std::max(t.depth, depth[i]);
    t.nodes.push_back(out);
  }
  t.meshes.push_back(m);
}

// ---------------------------------------------------------------------------------------------
// C. The helpers are the library's computations (mesh_distance.cpp, topology.cpp) operation for
// operation in double, so that compiled without FMA contraction they give its bits.

constexpr const char* kCHelpers = R"(#ifndef FREP_EXPORT_C_MESH_HELPERS
#define FREP_EXPORT_C_MESH_HELPERS
/* Exact signed distance to triangle meshes, in double: frep's MeshOracle operation for operation. */
typedef struct { double x, y, z; } frep_v3;
static inline frep_v3 frep_v3_make(double x, double y, double z) { frep_v3 r; r.x = x; r.y = y; r.z = z; return r; }
static inline frep_v3 frep_v3_at(const double* v, int i) { return frep_v3_make(v[3 * i], v[3 * i + 1], v[3 * i + 2]); }
static inline frep_v3 frep_v3_add(frep_v3 a, frep_v3 b) { return frep_v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline frep_v3 frep_v3_sub(frep_v3 a, frep_v3 b) { return frep_v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline frep_v3 frep_v3_scale(frep_v3 a, double s) { return frep_v3_make(a.x * s, a.y * s, a.z * s); }
static inline double frep_v3_dot(frep_v3 a, frep_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double frep_v3_length(frep_v3 a) { return sqrt(frep_v3_dot(a, a)); }
static inline frep_v3 frep_v3_cross(frep_v3 a, frep_v3 b) {
  return frep_v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* Unit normal of triangle abc along cross(b - a, c - a); zero if that is zero. */
static inline frep_v3 frep_face_normal(frep_v3 a, frep_v3 b, frep_v3 c) {
  const frep_v3 n = frep_v3_cross(frep_v3_sub(b, a), frep_v3_sub(c, a));
  const double l = frep_v3_length(n);
  return l > 0.0 ? frep_v3_make(n.x / l, n.y / l, n.z / l) : frep_v3_make(0.0, 0.0, 0.0);
}
static inline frep_v3 frep_closest_on_segment(frep_v3 p, frep_v3 a, frep_v3 b) {
  const frep_v3 ab = frep_v3_sub(b, a);
  const double l2 = frep_v3_dot(ab, ab);
  double t = l2 > 0.0 ? frep_v3_dot(frep_v3_sub(p, a), ab) / l2 : 0.0;
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return frep_v3_add(a, frep_v3_scale(ab, t));
}
/* Closest point to p on triangle abc (Ericson's regions); *f receives the feature it lies on:
 * 0 the face, 1 to 3 the edges ab, bc, ca, 4 to 6 the corners a, b, c. */
static inline frep_v3 frep_closest_on_triangle(frep_v3 p, frep_v3 a, frep_v3 b, frep_v3 c, int* f) {
  const frep_v3 ab = frep_v3_sub(b, a), ac = frep_v3_sub(c, a), ap = frep_v3_sub(p, a);
  const double d1 = frep_v3_dot(ab, ap), d2 = frep_v3_dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return *f = 4, a;
  const frep_v3 bp = frep_v3_sub(p, b);
  const double d3 = frep_v3_dot(ab, bp), d4 = frep_v3_dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return *f = 5, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) return *f = 1, frep_v3_add(a, frep_v3_scale(ab, d1 / (d1 - d3)));
  const frep_v3 cp = frep_v3_sub(p, c);
  const double d5 = frep_v3_dot(ab, cp), d6 = frep_v3_dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return *f = 6, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) return *f = 3, frep_v3_add(a, frep_v3_scale(ac, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
    return *f = 2, frep_v3_add(b, frep_v3_scale(frep_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) { /* collinear corners: the nearest of the three edges */
    const frep_v3 q0 = frep_closest_on_segment(p, a, b), q1 = frep_closest_on_segment(p, b, c),
                  q2 = frep_closest_on_segment(p, c, a);
    const double e0 = frep_v3_dot(frep_v3_sub(p, q0), frep_v3_sub(p, q0)),
                 e1 = frep_v3_dot(frep_v3_sub(p, q1), frep_v3_sub(p, q1)),
                 e2 = frep_v3_dot(frep_v3_sub(p, q2), frep_v3_sub(p, q2));
    if (e0 <= e1 && e0 <= e2) return *f = 1, q0;
    if (e1 <= e2) return *f = 2, q1;
    return *f = 3, q2;
  }
  {
    const double denom = 1.0 / sum, v = vb * denom, w = vc * denom;
    return *f = 0, frep_v3_add(frep_v3_add(a, frep_v3_scale(ab, v)), frep_v3_scale(ac, w));
  }
}
/* Squared distance from p to the box lo xyz, hi xyz. */
static inline double frep_box_gap(double lo, double hi, double x) { return x < lo ? lo - x : (x > hi ? x - hi : 0.0); }
static inline double frep_box_distance2(frep_v3 p, const float* box) {
  const double dx = frep_box_gap(box[0], box[3], p.x), dy = frep_box_gap(box[1], box[4], p.y),
               dz = frep_box_gap(box[2], box[5], p.z);
  return dx * dx + dy * dy + dz * dz;
}
/* Signed solid angle of triangle abc seen from p (Van Oosterom and Strackee). */
static inline double frep_solid_angle(frep_v3 p, frep_v3 a0, frep_v3 b0, frep_v3 c0) {
  const frep_v3 a = frep_v3_sub(a0, p), b = frep_v3_sub(b0, p), c = frep_v3_sub(c0, p);
  const double la = frep_v3_length(a), lb = frep_v3_length(b), lc = frep_v3_length(c);
  const double num = frep_v3_dot(a, frep_v3_cross(b, c));
  const double den = la * lb * lc + frep_v3_dot(a, b) * lc + frep_v3_dot(b, c) * la + frep_v3_dot(c, a) * lb;
  return 2.0 * atan2(num, den);
}
#endif
)";

// The walk. {P} is the prefix, {D} the stack size (the hierarchy's depth + 2).
constexpr const char* kCMesh = R"(
/* The signed distance to mesh `mesh` at p, in double (negative inside; NaN beyond |p| <= 1e150):
 * the nearest triangle by a nearest-first walk of the hierarchy, the distance to its closest
 * point, and the sign of the angle-weighted pseudonormal of the feature (face, edge or corner)
 * that point lies on, which is exact for closed solids (Baerentzen and Aanaes). */
static double {P}mesh(int mesh, double px, double py, double pz) {
  const frep_v3 p = frep_v3_make(px, py, pz);
  int stack[{D}], top = 1, best = -1, f = 0, t;
  double stack_d2[{D}], best_d2 = INFINITY, d, s;
  frep_v3 a, b, c, q, n;
  if (!(fabs(px) <= 1e150 && fabs(py) <= 1e150 && fabs(pz) <= 1e150)) return NAN;
  stack[0] = {P}meshes[3 * mesh];
  stack_d2[0] = 0.0;
  while (top > 0) {
    int node, first, count;
    --top;
    if (stack_d2[top] > best_d2) continue; /* a nearer triangle was found since it was pushed */
    node = stack[top];
    first = {P}nodes[2 * node];
    count = {P}nodes[2 * node + 1];
    if (count == 0) { /* both children, the nearer one on top */
      const double d0 = frep_box_distance2(p, {P}boxes + 6 * first), d1 = frep_box_distance2(p, {P}boxes + 6 * (first + 1));
      const int closer = d0 <= d1 ? first : first + 1;
      const double dn = d0 <= d1 ? d0 : d1, df = d0 <= d1 ? d1 : d0;
      if (df <= best_d2) stack[top] = 2 * first + 1 - closer, stack_d2[top++] = df;
      if (dn <= best_d2) stack[top] = closer, stack_d2[top++] = dn;
      continue;
    }
    for (t = first; t < first + count; ++t) {
      const int* v = {P}triangles + 3 * t;
      const frep_v3 e = frep_v3_sub(p, frep_closest_on_triangle(p, frep_v3_at({P}vertices, v[0]),
                                      frep_v3_at({P}vertices, v[1]), frep_v3_at({P}vertices, v[2]), &f));
      const double d2 = frep_v3_dot(e, e);
      if (d2 < best_d2) best_d2 = d2, best = t;
    }
  }
  if (best < 0) return NAN; /* not reached: squared distances are finite below 1e150 */
  a = frep_v3_at({P}vertices, {P}triangles[3 * best]);
  b = frep_v3_at({P}vertices, {P}triangles[3 * best + 1]);
  c = frep_v3_at({P}vertices, {P}triangles[3 * best + 2]);
  q = frep_closest_on_triangle(p, a, b, c, &f);
  n = frep_face_normal(a, b, c);
  /* In the face's prism, the distance to its plane: free of the rounding of q's coordinates. */
  d = f == 0 && frep_v3_dot(n, n) > 0.0 ? fabs(frep_v3_dot(frep_v3_sub(p, a), n)) : frep_v3_length(frep_v3_sub(p, q));
  if (d == 0.0) return 0.0;
  if (f >= 4) { /* a corner: its stored pseudonormal */
    n = frep_v3_at({P}vertex_normals, {P}triangles[3 * best + f - 4]);
  } else if (f >= 1) { /* an edge: the sum of its two faces' normals */
    const int* u = {P}triangles + 3 * {P}neighbours[3 * best + f - 1];
    n = frep_v3_add(n, frep_face_normal(frep_v3_at({P}vertices, u[0]), frep_v3_at({P}vertices, u[1]),
                                        frep_v3_at({P}vertices, u[2])));
  }
  s = frep_v3_dot(frep_v3_sub(p, q), n);
  if (s != 0.0) return s > 0.0 ? d : -d;
  /* p - q perpendicular to the pseudonormal (rounding): the winding number decides, as in frep. */
  s = 0.0;
  for (t = {P}meshes[3 * mesh + 1]; t < {P}meshes[3 * mesh + 1] + {P}meshes[3 * mesh + 2]; ++t) {
    const int* v = {P}triangles + 3 * t;
    s += frep_solid_angle(p, frep_v3_at({P}vertices, v[0]), frep_v3_at({P}vertices, v[1]), frep_v3_at({P}vertices, v[2]));
  }
  return s / (4.0 * 3.14159265358979323846) > 0.5 ? -d : d;
}
)";

// The text of an affine map's row i applied to the point (x, y, z) in C: every term written, in
// frep's order (0 * inf is NaN in frep's map too).
std::string c_map_row(const Affine3& a, int i) {
  return c_double(a.m[i][0]) + " * x + " + c_double(a.m[i][1]) + " * y + " + c_double(a.m[i][2]) + " * z + " +
         c_double(a.m[i][3]);
}

// The same in GLSL, in float: zero terms left out, unit coefficients unwritten (a GPU computes
// in float anyway, and the rows read like the map).
std::string glsl_map_row(const Affine3& a, int i) {
  static const char* const var[3] = {"p.x", "p.y", "p.z"};
  std::string s;
  for (int k = 0; k < 4; ++k) {
    const float c = static_cast<float>(a.m[i][k]);
    if (c == 0) continue;
    const bool negative = c < 0;
    s += s.empty() ? (negative ? "-" : "") : (negative ? " - " : " + ");
    const float m = negative ? -c : c;
    if (k == 3) s += glsl_float(m);
    else s += m == 1 ? var[k] : glsl_float(m) + " * " + var[k];
  }
  return s.empty() ? "0.0" : s;
}

// ---------------------------------------------------------------------------------------------
// GLSL: the same walk in float, with vec3.

constexpr const char* kGlslMesh = R"(
// Squared distance from p to triangle abc, e = p minus the closest point, and the feature that
// point lies on in f: 0 the face, 1 to 3 the edges ab, bc, ca, 4 to 6 the corners a, b, c.
// Robust in float for long thin triangles: the plane's distance inside the prism (tests against
// the edges' planes), else the nearest of the three edges (clamped projections); no barycentric
// products, whose cancellation misplaces the closest point of such triangles.
float {P}closest(vec3 p, vec3 a, vec3 b, vec3 c, out vec3 e, out int f) {
  vec3 ab = b - a, bc = c - b, ca = a - c, pa = p - a, pb = p - b, pc = p - c, n = cross(ab, c - a);
  float nn = dot(n, n);
  if (nn > 0.0 && dot(cross(ab, n), pa) <= 0.0 && dot(cross(bc, n), pb) <= 0.0 && dot(cross(ca, n), pc) <= 0.0) {
    n *= inversesqrt(nn);
    float s = dot(pa, n);
    e = n * s;
    f = 0;
    return s * s;
  }
  float best = uintBitsToFloat(0x7f800000u);
  for (int k = 0; k < 3; k++) {
    vec3 d = k == 0 ? ab : (k == 1 ? bc : ca), o = k == 0 ? pa : (k == 1 ? pb : pc);
    float l = dot(d, d), t = l > 0.0 ? clamp(dot(o, d) / l, 0.0, 1.0) : 0.0;
    vec3 g = o - d * t;
    float d2 = dot(g, g);
    if (d2 < best || k == 0) {
      best = d2;
      e = g;
      f = t == 0.0 ? 4 + k : (t == 1.0 ? 4 + (k + 1) % 3 : 1 + k);
    }
  }
  return best;
}

// The corners' vertices of triangle t (the low halves of its entry; the high ones are the
// neighbours).
ivec3 {P}corners(int t) { return ivec3({P}triangles[t] & 0xffffu); }

vec3 {P}normal(int t) {
  ivec3 v = {P}corners(t);
  vec3 n = cross({P}vertices[v.y] - {P}vertices[v.x], {P}vertices[v.z] - {P}vertices[v.x]);
  float l = length(n);
  return l > 0.0 ? n / l : vec3(0.0);
}

float {P}box2(vec3 p, int node) {
  vec3 g = max(max({P}lo[node] - p, p - {P}hi[node]), vec3(0.0));
  return dot(g, g);
}

// The signed distance to mesh `mesh` at p (negative inside): the nearest triangle by a
// nearest-first walk of the hierarchy, the distance to its closest point, and the sign of the
// angle-weighted pseudonormal of the feature that point lies on (exact for closed solids).
float {P}mesh(int mesh, vec3 p) {
  int stack[{D}];
  float stack_d2[{D}];
  int top = 1, best = -1, best_f = 0, f;
  float best_d2 = uintBitsToFloat(0x7f800000u);
  vec3 best_e = vec3(0.0), e;
  stack[0] = {P}roots[mesh];
  stack_d2[0] = 0.0;
  while (top > 0) {
    top--;
    if (stack_d2[top] > best_d2) continue;  // a nearer triangle was found since it was pushed
    ivec2 node = {P}nodes[stack[top]];
    if (node.y == 0) {  // both children, the nearer one on top
      float d0 = {P}box2(p, node.x), d1 = {P}box2(p, node.x + 1);
      int closer = d0 <= d1 ? node.x : node.x + 1;
      if (max(d0, d1) <= best_d2) {
        stack[top] = 2 * node.x + 1 - closer;
        stack_d2[top++] = max(d0, d1);
      }
      if (min(d0, d1) <= best_d2) {
        stack[top] = closer;
        stack_d2[top++] = min(d0, d1);
      }
      continue;
    }
    for (int t = node.x; t < node.x + node.y; t++) {
      ivec3 v = {P}corners(t);
      float d2 = {P}closest(p, {P}vertices[v.x], {P}vertices[v.y], {P}vertices[v.z], e, f);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = t;
        best_e = e;
        best_f = f;
      }
    }
  }
  if (best < 0) return uintBitsToFloat(0x7fc00000u);  // p is NaN or infinite
  ivec3 v = {P}corners(best), across = ivec3({P}triangles[best] >> 16u);
  vec3 n = {P}normal(best);
  if (best_f >= 4) n = {P}vertex_normals[best_f == 4 ? v.x : (best_f == 5 ? v.y : v.z)];
  else if (best_f >= 1) n += {P}normal(best_f == 1 ? across.x : (best_f == 2 ? across.y : across.z));
  float d = sqrt(best_d2);
  return dot(best_e, n) < 0.0 ? -d : d;
}
)";

}  // namespace

bool only_mesh_oracles(const Graph& g, const std::vector<NodeId>& order) {
  for (NodeId id : order)
    if (g.node(id).op == Op::Oracle && !as_mesh_oracle(g, id)) return false;
  return true;
}

Model expand_other_oracles(const Graph& g, NodeId root) {
  Model m;
  const std::vector<NodeId> order = reachable_nodes(g, root);
  std::vector<NodeId> id(root + 1, kNoNode);
  for (NodeId n : order) {
    const Node& node = g.node(n);
    if (node.op == Op::Oracle) {
      const auto& o = g.oracles()[oracle_index(node.value)];
      id[n] = as_mesh_oracle(g, n) ? m.graph->oracle(o) : o->closed_form(*m.graph);
      continue;
    }
    id[n] = m.graph->make(node.op, node.a == kNoNode ? kNoNode : id[node.a], node.b == kNoNode ? kNoNode : id[node.b],
                          node.value);
  }
  m.root = id[root];
  return m;
}

MeshTables mesh_tables(const Graph& g, const std::vector<NodeId>& order) {
  MeshTables t;
  for (NodeId id : order) {
    const Node& n = g.node(id);
    if (n.op != Op::Oracle) continue;
    MeshTables::Use use;
    const MeshOracle* mesh = as_mesh_oracle(g, id, &use.map);
    FREP_ASSERT(mesh, "an oracle that is not a mesh in the data form of an export");
    use.oracle = oracle_index(n.value);
    use.moved = !use.map.is_identity();
    std::size_t k = 0;
    while (k < t.meshes.size() && t.meshes[k].oracle != mesh) ++k;
    if (k == t.meshes.size()) add_mesh(t, *mesh);
    use.mesh = static_cast<std::uint32_t>(k);
    t.uses.push_back(use);
  }
  std::sort(t.uses.begin(), t.uses.end(), [](const auto& a, const auto& b) { return a.oracle < b.oracle; });
  return t;
}

std::string mesh_summary(const MeshTables& t) {
  return thousands(t.meshes.size()) + (t.meshes.size() == 1 ? " mesh, " : " meshes, ") + thousands(t.triangles.size()) +
         " triangles, " + thousands(t.vertices.size()) + " vertices";
}

void write_c_meshes(std::ostream& out, const std::string& prefix, const MeshTables& t) {
  out << "\n" << kCHelpers;
  out << "\n/* The meshes: " << mesh_summary(t)
      << ". Triangles are in the leaf order of a\n"
         " * bounding-box hierarchy, so that each leaf holds a run of them. */\n";
  auto ints = [&](const char* name, const char* what, std::size_t n, auto&& each) {
    out << "static const int " << prefix << name << "[" << n << "] = { /* " << what << " */\n";
    ArrayWriter w(out);
    each(w);
    w.end();
    out << "};\n";
  };
  auto doubles = [&](const char* name, const char* what, const std::vector<Vec3>& v) {
    out << "static const double " << prefix << name << "[" << 3 * v.size() << "] = { /* " << what << " */\n";
    ArrayWriter w(out);
    for (const Vec3& p : v)
      for (int k = 0; k < 3; ++k) w.item(c_double(p[k]));
    w.end();
    out << "};\n";
  };
  doubles("vertices", "x, y, z per vertex", t.vertices);
  doubles("vertex_normals", "angle-weighted pseudonormal per vertex", t.vertex_normals);
  ints("triangles", "the corners' vertices per triangle", 3 * t.triangles.size(), [&](ArrayWriter& w) {
    for (const auto& tri : t.triangles)
      for (std::uint32_t v : tri) w.item(std::to_string(v));
  });
  ints("neighbours", "per triangle, the triangle across each edge (corners k, k + 1)", 3 * t.neighbours.size(),
       [&](ArrayWriter& w) {
         for (const auto& tri : t.neighbours)
           for (std::uint32_t v : tri) w.item(std::to_string(v));
       });
  out << "static const float " << prefix << "boxes[" << 6 * t.nodes.size()
      << "] = { /* per hierarchy node: lo x, y, z, hi x, y, z (rounded outward) */\n";
  {
    ArrayWriter w(out);
    for (const auto& n : t.nodes) {
      for (float v : n.lo) w.item(c_float(v));
      for (float v : n.hi) w.item(c_float(v));
    }
    w.end();
    out << "};\n";
  }
  ints("nodes", "per node: first triangle, count (leaves); first child, 0 (inner nodes: children first, first + 1)",
       2 * t.nodes.size(), [&](ArrayWriter& w) {
         for (const auto& n : t.nodes) {
           w.item(std::to_string(n.first));
           w.item(std::to_string(n.count));
         }
       });
  ints("meshes", "per mesh: root node, first triangle, triangle count", 3 * t.meshes.size(), [&](ArrayWriter& w) {
    for (const auto& m : t.meshes) {
      w.item(std::to_string(m.root));
      w.item(std::to_string(m.first_triangle));
      w.item(std::to_string(m.triangles));
    }
  });
  out << fill(kCMesh, prefix, t.depth + 2);
  // One function per oracle: the mesh at the point, mapped as frep maps it (in double from the
  // float point, each coordinate rounded to float), the distance rounded once to float.
  out << "\n";
  for (const MeshTables::Use& u : t.uses) {
    out << "static float " << prefix << "oracle" << u.oracle << "(float x, float y, float z) {\n  return (float)"
        << prefix << "mesh(" << u.mesh << ",";
    if (!u.moved) {
      out << " x, y, z);\n}\n";
      continue;
    }
    for (int i = 0; i < 3; ++i) out << (i ? ",\n      " : "\n      ") << "(float)(" << c_map_row(u.map, i) << ")";
    out << ");\n}\n";
  }
}

std::size_t glsl_mesh_bytes(const MeshTables& t) {
  // vec3 and uvec3 take 12 bytes, ivec2 8: vertices and their normals, triangles, node boxes
  // and ranges, roots.
  return 24 * t.vertices.size() + 12 * t.triangles.size() + 32 * t.nodes.size() + 4 * t.meshes.size();
}

void check_glsl_meshes(const MeshTables& t) {
  const std::size_t bytes = glsl_mesh_bytes(t);
  if (bytes > kMaxGlslMeshBytes)
    throw InputError("", 0,
                     "the meshes (" + thousands(t.triangles.size()) + " triangles) need " + thousands(bytes) +
                         " bytes of constant arrays in GLSL, more than the " + thousands(kMaxGlslMeshBytes) +
                         " GPU compilers take (Mesa's does not finish beyond; about 1,900 triangles): simplify the "
                         "mesh, or use --closed-form (GlslOptions::closed_form) for its closed form, ~75 nodes per "
                         "triangle, which GPU compilers handle up to a few hundred triangles");
  double largest = 0, extent = 0;
  Box3 box;
  for (const Vec3& v : t.vertices) {
    box.add(v);
    largest = std::max({largest, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  }
  const Vec3 size = box.size();
  extent = std::max({size.x, size.y, size.z});
  // Squared normals (size^4) stay finite and normal in float.
  if (largest > 1e9 || extent < 1e-9)
    throw InputError("", 0,
                     "the GLSL export computes mesh distances in float, which needs coordinates within 1e9 and a size "
                     "above 1e-9: rescale the mesh, or use --closed-form (GlslOptions::closed_form)");
}

void write_glsl_meshes(std::ostream& out, const std::string& prefix, const MeshTables& t) {
  out << "\n// The meshes: " << mesh_summary(t)
      << ", in float. Triangles are in the leaf order of a\n"
         "// bounding-box hierarchy, so that each leaf holds a run of them.\n";
  // Arrays are written `const T name[N] = T[N](` ... `);`, the closing line alone.
  auto open = [&](const char* type, const char* name, std::size_t n, const char* what) {
    out << "const " << type << " " << prefix << name << "[" << n << "] = " << type << "[" << n << "](  // " << what << "\n";
  };
  auto close = [&](ArrayWriter& w) {
    w.end();
    out << ");\n";
  };
  auto vec3_text = [](const Vec3& v) {
    return "vec3(" + glsl_float(static_cast<float>(v.x)) + ", " + glsl_float(static_cast<float>(v.y)) + ", " +
           glsl_float(static_cast<float>(v.z)) + ")";
  };
  {
    open("vec3", "vertices", t.vertices.size(), "per vertex");
    ArrayWriter w(out);
    for (const Vec3& v : t.vertices) w.item(vec3_text(v));
    close(w);
  }
  {
    open("vec3", "vertex_normals", t.vertex_normals.size(), "per vertex, the angle-weighted pseudonormal, normalized");
    ArrayWriter w(out);
    for (const Vec3& n : t.vertex_normals) {
      const double l = length(n);
      w.item(vec3_text(l > 0 ? n / l : Vec3{}));
    }
    close(w);
  }
  {
    // Both 16-bit: kMaxGlslMeshBytes keeps the data far below 65536 vertices and triangles.
    FREP_ASSERT(t.vertices.size() <= 0xffff && t.triangles.size() <= 0xffff, "GLSL mesh data beyond 16-bit indices");
    open("uvec3", "triangles", t.triangles.size(),
         "per triangle and corner k: its vertex + 65536 * the triangle across the edge from corner k to k + 1");
    ArrayWriter w(out);
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
      std::string item = "uvec3(";
      for (int k = 0; k < 3; ++k)
        item += (k ? ", " : "") + std::to_string(t.triangles[i][k] | t.neighbours[i][k] << 16) + "u";
      w.item(item + ")");
    }
    close(w);
  }
  for (int side = 0; side < 2; ++side) {
    open("vec3", side ? "hi" : "lo", t.nodes.size(), side ? "per hierarchy node, the box's upper corner (rounded outward)"
                                                         : "per hierarchy node, the box's lower corner (rounded outward)");
    ArrayWriter w(out);
    for (const auto& n : t.nodes) {
      const float* c = side ? n.hi : n.lo;
      w.item("vec3(" + glsl_float(c[0]) + ", " + glsl_float(c[1]) + ", " + glsl_float(c[2]) + ")");
    }
    close(w);
  }
  {
    open("ivec2", "nodes", t.nodes.size(), "per node: first triangle, count (leaves); first child, 0 (inner nodes)");
    ArrayWriter w(out);
    for (const auto& n : t.nodes) w.item("ivec2(" + std::to_string(n.first) + ", " + std::to_string(n.count) + ")");
    close(w);
  }
  {
    open("int", "roots", t.meshes.size(), "per mesh, its root node");
    ArrayWriter w(out);
    for (const auto& m : t.meshes) w.item(std::to_string(m.root));
    close(w);
  }
  out << fill(kGlslMesh, prefix, t.depth + 2);
  out << "\n";
  for (const MeshTables::Use& u : t.uses) {
    out << "float " << prefix << "oracle" << u.oracle << "(vec3 p) { return " << prefix << "mesh(" << u.mesh << ", ";
    if (!u.moved) {
      out << "p); }\n";
      continue;
    }
    out << "vec3(";
    for (int i = 0; i < 3; ++i) out << (i ? ",\n    " : "\n    ") << glsl_map_row(u.map, i);
    out << ")); }\n";
  }
}

}  // namespace frep::export_detail
