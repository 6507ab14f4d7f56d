// frep::convert_mesh: check, weld, extract features, build the terms, combine them, and sign.
#include "frep/convert/convert.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <chrono>
#include <cmath>
#include <map>

#include "convert/build.hpp"
#include "convert/features.hpp"
#include "convert/tetgen.hpp"
#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/math/predicates.hpp"
#include "frep/mesh/coordinate_range.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/weld.hpp"

namespace frep {
namespace {

using namespace convert_detail;

void report(const ConvertOptions& o, const char* stage, double fraction) {
  if (o.progress) o.progress(stage, fraction);
}

// Inside test from the tetrahedra: M = max over tetrahedra of the min of their four inward plane
// values, >= 0 inside the union. Surface faces use the regions' own planes (exactly 0 on the
// surface); a face between two tetrahedra is one value, negated for one of them.
// The vertices of the vertex bound (see ExprBuilder::vertex_bound): ends of crease edges and the
// vertex terms' vertices, at most one per cell of a grid twice the mean crease length (the bound
// holds for any set of surface points; this keeps it tight at a fraction of the nodes). Never
// vertices inside flat regions, so that the tessellation of flat faces still costs nothing.
std::vector<std::uint32_t> bound_vertices(const Features& f, const std::vector<Vec3>& points) {
  std::vector<std::uint32_t> vs;
  double total = 0;
  for (const EdgeTerm& e : f.edges) {
    vs.push_back(e.a), vs.push_back(e.b);
    total += length(points[e.b] - points[e.a]);
  }
  for (const VertexTerm& v : f.vertices) vs.push_back(v.v);
  std::sort(vs.begin(), vs.end());
  vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
  const double cell = f.edges.empty() ? 0.0 : 2.0 * total / static_cast<double>(f.edges.size());
  if (!(cell > 0)) return vs;
  std::unordered_set<std::uint64_t> seen;
  std::vector<std::uint32_t> kept;
  for (std::uint32_t v : vs) {
    std::uint64_t key = 0;
    for (int k = 0; k < 3; ++k)
      key = key * 2097152u + static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(points[v][k] / cell)) & 0x1FFFFF);
    if (seen.insert(key).second) kept.push_back(v);
  }
  return kept;
}

NodeId inside_measure(ExprBuilder& b, const TriMesh& m, const Features& f, const Tetrahedralization& tz) {
  Graph& g = b.graph();
  using Key = std::array<std::uint32_t, 3>;
  std::map<Key, std::uint32_t> surface;  // sorted corners -> triangle
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    if (f.region_of[t] == MeshTopology::kNone) continue;
    Key k = m.triangles[t];
    std::sort(k.begin(), k.end());
    surface.emplace(k, t);
  }
  std::map<Key, NodeId> lines;  // interior face -> (p - a) . n with (a, b, c) sorted, n = unit (b - a) x (c - a)
  std::vector<NodeId> tet_values;
  std::vector<Vec3> centers;
  tet_values.reserve(tz.tets.size());
  for (const auto& t : tz.tets) {
    NodeId value = kNoNode;
    for (int k = 0; k < 4; ++k) {
      Key key{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
      std::sort(key.begin(), key.end());
      const std::uint32_t opposite = t[static_cast<std::size_t>(k)];
      NodeId v;
      if (auto s = surface.find(key); s != surface.end()) {
        v = g.unary(Op::Neg, b.plane(f.region_of[s->second]));  // the solid is behind its outward plane
      } else {
        auto it = lines.find(key);
        if (it == lines.end()) {
          const Vec3 &pa = b.point(key[0]), &pb = b.point(key[1]), &pc = b.point(key[2]);
          Vec3 n = cross(pb - pa, pc - pa);
          const double len = length(n);
          FREP_ASSERT(len > 0, "flat tetrahedron face");
          it = lines.emplace(key, b.linear(key[0], n / len)).first;
        }
        // The two tetrahedra of the face see one value with opposite signs (negation is exact),
        // so a point on it is on the non-negative side of at least one of them: no float crack.
        const bool toward = exact::orient3d(tz.points[key[0]], tz.points[key[1]], tz.points[key[2]], tz.points[opposite]) > 0;
        v = toward ? it->second : g.unary(Op::Neg, it->second);
      }
      value = value == kNoNode ? v : g.binary(Op::Min, value, v);
    }
    tet_values.push_back(value);
    centers.push_back((tz.points[t[0]] + tz.points[t[1]] + tz.points[t[2]] + tz.points[t[3]]) * 0.25);
  }
  Box3 box;
  for (const Vec3& c : centers) box.add(c);
  const std::vector<std::uint32_t> order = morton_order(centers, box);
  return balanced_tree<NodeId>(
      tet_values.size(), [&](std::size_t i) { return tet_values[order[i]]; },
      [&](NodeId x, NodeId y) { return g.binary(Op::Max, x, y); });
}

}  // namespace

void check_convertible(const std::string& name, const ValidationReport& check) {
  if (!check.is_solid()) throw InputError(name, 0, "cannot convert: " + check.summary() + " (frep check shows where)");
  if (const Defect& z = check.defect(DefectKind::ZeroAreaTriangles); z.count > 0) {
    std::string where;
    if (!z.examples.empty()) {
      const DefectLocation& l = z.examples.front();
      where = " (the first is triangle " + std::to_string(l.triangle) + (l.line ? ", line " + std::to_string(l.line) : "") + ")";
    }
    throw InputError(name, 0, "cannot convert: " + std::to_string(z.count) +
                                  " zero-area triangles (collinear corners) have no normal, so the sign of "
                                  "the distance is undefined next to them" + where + "; remove them first");
  }
}

ConvertResult convert_mesh(const TriMesh& mesh, const ConvertOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!(o.tetgen_timeout > 0)) throw InputError(mesh.name, 0, "the TetGen time limit must be positive");
  // Before the check: a mesh beyond float range or precision is refused for what it is (the
  // check's exact predicates would see a valid solid or a flat one), naming the vertex.
  check_coordinate_range(mesh);
  report(o, "checking", 0.0);
  ValidationOptions vo;
  vo.weld_tolerance = o.weld_tolerance;
  vo.threads = o.threads;
  check_convertible(mesh.name, validate_mesh(mesh, vo));
  report(o, "features", 0.3);
  const WeldResult w = weld(mesh, {o.weld_tolerance});
  const TriMesh& m = w.mesh;
  const MeshTopology topo(m);
  const Features f = extract_features(m, topo);

  ConvertResult r;
  ConvertStats& st = r.stats;
  st.triangles = topo.num_usable_triangles();
  st.vertices = topo.num_used_vertices();
  st.flat_regions = f.regions.size();
  for (const Region& reg : f.regions) st.polygons += reg.polygons.size();
  st.edge_terms = f.edges.size();
  for (const Triangle& t : m.triangles)
    for (std::uint32_t v : t) st.box.add(m.vertices[v]);

  // The frame (see Frame): a mesh far from the origin (its centre farther than its diagonal)
  // works relative to its centre; huge or tiny ones (beyond 2^+-20) in units of a power of two
  // S, the result scaled back by S.
  const Box3 mbox = bounding_box(m);
  const double diag = length(mbox.size());
  Frame frame;
  const Vec3 center = mbox.center();
  if (length(center) > diag) frame.origin = Vec3f(center);
  double extent = diag;
  for (const Vec3& v : m.vertices)
    for (int k = 0; k < 3; ++k) extent = std::max(extent, std::fabs(v[k] - frame.origin[k]));
  const int e = extent > 0 ? std::clamp(std::ilogb(extent), -126, 127) : 0;
  const double s = (e < -20 || e > 20) ? std::ldexp(1.0, e) : 1.0;
  frame.scale = static_cast<float>(1.0 / s);
  // Reach of prism tests past internal polygon edges: a few float roundings of the coordinates.
  const double margin = 0x1p-20 * extent / s;

  Graph& g = *r.model.graph;
  g.reserve(80 * st.triangles);  // about what meshes take (docs/convert.md)
  Tetrahedralization tz;
  if (o.sign == SignMode::Tetrahedra) {
    report(o, "tetgen", 0.4);
    tz = tetrahedralize(m, o.tetgen, o.tetgen_timeout);
    st.tetrahedra = tz.tets.size();
  } else {
    st.vertex_terms = f.vertices.size();
  }
  report(o, "building", 0.7);
  std::vector<Vec3> points = o.sign == SignMode::Tetrahedra ? tz.points : m.vertices;
  for (Vec3& p : points) p = (p - Vec3(frame.origin)) / s;
  Box3 box;
  for (const Vec3& p : points) box.add(p);
  // Far from the mesh, intervals cannot tell which feature is nearest, so they cannot bound
  // the distance away from 0 (the bounds search of frep mesh would see an unbounded field).
  // The signed distance to a box holding the solid is below the solid's own everywhere (a
  // subset's distance is never smaller, inside or out), and strictly below it for a slightly
  // grown box: max(distance, box distance) is the distance, bit for bit, yet its interval far
  // away starts at the box distance.
  //
  // Very far away (2^64 frame units), the terms' squares overflow f32 and the field would be inf.
  // Beyond 2^60 units from the box on some axis, the distance to the box, computed in units of
  // 2^66 (exact scalings: no square overflows for any float point, none underflows that far), is
  // the distance to within the box's size, below a float's rounding there: it replaces the
  // field. Nearer, the select is the field bit for bit (intervals settle it). The max with the
  // box's Chebyshev distance `inside`, a lower bound of the signed distance everywhere (inside the
  // box too: the solid lies in it), keeps the intervals of boxes reaching that far off 0.
  const auto with_box_bound = [&](ExprBuilder& b, NodeId root) {
    const std::array<NodeId, 3> xyz = b.coords();
    const double grow = 1e-3 * length(box.size()) + margin;
    Expr outside(g, g.constant(0.0f)), inside(g, kNoNode), far2(g, kNoNode);
    for (int k = 0; k < 3; ++k) {
      const Expr q = abs(Expr(g, xyz[k]) - static_cast<float>(box.center()[k])) -
                     static_cast<float>(0.5 * box.size()[k] + grow);
      outside = outside + square(max(q, 0.0f));
      inside = k == 0 ? q : max(inside, q);
      const Expr scaled = square(max(q, 0.0f) * 0x1p-66f);
      far2 = k == 0 ? scaled : far2 + scaled;
    }
    const Expr near = max(Expr(g, root), sqrt(outside) + min(inside, 0.0f));
    const Expr far = sqrt(far2) * 0x1p66f;
    return max(logical_or(logical_and(max(inside - 0x1p60f, 0.0f), far), near), inside).id();
  };
  if (o.sign == SignMode::Pseudonormal) {
    ExprBuilder b(g, points, f, margin, frame);
    Term root = b.distance(true, box);
    // The vertex bound B (see vertex_bound) is above the computed min(P, N) everywhere: where
    // P <= N, min(P, B) = P; where P > N, min(P, B) and min(N, B) = N keep their order. So the
    // field is unchanged bit for bit, and interval pruning drops every term of P and N that
    // starts beyond B over a box (eval/caps.hpp). Intervals then cannot settle the sign near the
    // surface (min(P, B) meets min(N, B)); the field is an exact distance, so frep's renderers
    // and meshers settle boxes from the value at their centre instead (FieldInfo::lipschitz), and the
    // tight bound halves what a box keeps (docs/convert.md, "The vertex bound").
    const NodeId bound = b.vertex_bound(bound_vertices(f, points), box, extent / s);
    root.d2 = g.binary(Op::Min, root.d2, bound);
    root.neg = g.binary(Op::Min, root.neg, bound);
    // sqrt(P) where P <= N, else -sqrt(N): compare(P, N) > 0 exactly where the nearest feature is
    // an inside one.
    const Expr inside = max(compare(Expr(g, root.d2), Expr(g, root.neg)), 0.0f);
    r.model.root = with_box_bound(b, if_nonzero_else(inside, -sqrt(Expr(g, root.neg)), sqrt(Expr(g, root.d2))).id());
  } else {
    // Unsigned terms only: vertex terms exist to settle signs, which the tetrahedra do here.
    Features uf = f;
    uf.vertices.clear();
    for (EdgeTerm& e : uf.edges) e.interpolate = false;
    ExprBuilder b(g, points, uf, margin, frame);
    const Term root = b.distance(false, box);
    // min(U, vertex bound) = U (see above).
    const Expr dist(g, g.unary(Op::Sqrt, g.binary(Op::Min, root.d2, b.vertex_bound(bound_vertices(f, points), box, extent / s))));
    // compare(M, 0) + 1 is non-zero exactly where M >= 0: inside.
    const Expr inside = compare(Expr(g, inside_measure(b, m, uf, tz)), 0.0f) + 1.0f;
    r.model.root = with_box_bound(b, if_nonzero_else(inside, -dist, dist).id());
  }
  if (s != 1.0) r.model.root = g.binary(Op::Mul, r.model.root, g.constant(static_cast<float>(s)));
  r.model.info.lipschitz = 1;  // an exact distance (both sign methods), in the mesh's own units
  r.model.info.bounds = st.box;  // the solid is inside its triangles' bounding box
  r.model.info.growth = Growth::Distance;  // an exact distance: offsets grow the box by their distance
  st.nodes = reachable_nodes(g, r.model.root).size();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report(o, "done", 1.0);
  return r;
}

}  // namespace frep
