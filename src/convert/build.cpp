// The distance expression's terms. Everything is a squared distance (one square root at the
// root), built from the per-vertex offsets p - v so that neighbouring features share nodes:
//   region:  h = (p - anchor) . n; inside the region's prism the term is h^2, outside it is huge:
//            max(h^2, K q) where q <= 0 exactly inside the prism. The prism is the union of the
//            region's convex polygons, each the intersection of half-spaces over its edges
//            (widened by a margin at internal edges, so neighbouring polygons overlap instead of
//            leaving float cracks).
//   edge:    t = (p - a) . d / |d|^2 clamped to [0, 1], w = (p - a) - t d, term |w|^2 (branch
//            free, and equal to the distance to an endpoint beyond the segment); t is carried
//            scaled by |d_m| (d's largest component) so that one step component is exactly 1.
//   vertex:  |p - v|^2, shrunk by a few ulps so that it wins exact ties with the edges that end
//            there (their clamped value is bit-identical at that end).
// Linear forms used only for their sign (prism sides, pseudonormal tests) are scaled so that
// one coefficient is exactly 1: fewer constants and multiplications.
// Signs (see Term): a cluster (a region and its gentle creases) is tested by h; a sharp crease by
// h1 + h2 (its pseudonormal n1 + n2); a vertex by (p - v) . N_v.
#include "convert/build.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/error.hpp"
#include "util/morton.hpp"

namespace frep::convert_detail {
namespace {

// Outside its prism, a plane term is at least K times how far outside (in the sides' own
// units): far larger than any squared distance, except within float-invisible reach of the prism.
constexpr float kGate = 1e30f;
// Vertex terms are scaled by this to win exact ties (2^-20 relative: far above one rounding,
// far below the accuracy that matters).
constexpr float kVertexShrink = 1.0f - 0x1p-20f;

int largest_axis(const Vec3& c) {
  const double ax = std::fabs(c.x), ay = std::fabs(c.y), az = std::fabs(c.z);
  return ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
}

}  // namespace

ExprBuilder::ExprBuilder(Graph& g, const std::vector<Vec3>& points, const Features& features, double margin,
                         const Frame& frame)
    : g_(g), pts_(points), f_(features), margin_(margin) {
  NodeId v[3] = {g.var_x(), g.var_y(), g.var_z()};
  for (int k = 0; k < 3; ++k) {
    if (frame.origin[k] != 0.0f) v[k] = g.binary(Op::Sub, v[k], g.constant(frame.origin[k]));
    if (frame.scale != 1.0f) v[k] = g.binary(Op::Mul, v[k], g.constant(frame.scale));
  }
  x_ = v[0], y_ = v[1], z_ = v[2];
  offset_.assign(points.size(), {kNoNode, kNoNode, kNoNode});
  plane_.assign(features.regions.size(), kNoNode);
}

const std::array<NodeId, 3>& ExprBuilder::offset(std::uint32_t v) {
  std::array<NodeId, 3>& o = offset_[v];
  if (o[0] == kNoNode) {
    const Vec3& p = pts_[v];
    o = {g_.binary(Op::Sub, x_, g_.constant(static_cast<float>(p.x))),
         g_.binary(Op::Sub, y_, g_.constant(static_cast<float>(p.y))),
         g_.binary(Op::Sub, z_, g_.constant(static_cast<float>(p.z)))};
  }
  return o;
}

NodeId ExprBuilder::linear(std::uint32_t v, const Vec3& c) {
  const auto& o = offset(v);
  NodeId sum = kNoNode;
  for (int k = 0; k < 3; ++k) {
    const float ck = static_cast<float>(c[k]);
    if (ck == 0.0f) continue;
    const NodeId ok = o[static_cast<std::size_t>(k)];
    if (sum == kNoNode) {
      sum = g_.binary(Op::Mul, ok, g_.constant(ck));
    } else if (ck == 1.0f || ck == -1.0f) {
      sum = g_.binary(ck > 0 ? Op::Add : Op::Sub, sum, ok);
    } else {
      sum = g_.binary(Op::Add, sum, g_.binary(Op::Mul, ok, g_.constant(ck)));
    }
  }
  return sum == kNoNode ? g_.constant(0.0f) : sum;
}

NodeId ExprBuilder::sign_form(std::uint32_t v, const Vec3& c, double& scale) {
  const int m = largest_axis(c);
  scale = std::fabs(c[m]);
  FREP_ASSERT(scale > 0, "zero linear form");
  // Start from the unit coefficient so it needs no multiplication.
  Vec3 s = c / scale;
  const auto& o = offset(v);
  NodeId sum = s[m] > 0 ? o[static_cast<std::size_t>(m)] : g_.unary(Op::Neg, o[static_cast<std::size_t>(m)]);
  s[m] = 0;
  for (int k = 0; k < 3; ++k) {
    const float ck = static_cast<float>(s[k]);
    if (ck == 0.0f) continue;
    sum = g_.binary(Op::Add, sum, g_.binary(Op::Mul, o[static_cast<std::size_t>(k)], g_.constant(ck)));
  }
  return sum;
}

NodeId ExprBuilder::plane(std::uint32_t r) {
  if (plane_[r] == kNoNode) plane_[r] = linear(f_.regions[r].anchor, f_.regions[r].normal);
  return plane_[r];
}

NodeId ExprBuilder::region_term(std::uint32_t r) {
  const Region& reg = f_.regions[r];
  const NodeId h = plane(r);
  // Per polygon: the largest "outside" amount over its edges (<= 0 inside); over the region: the
  // smallest of those (<= 0 inside some polygon).
  std::vector<NodeId> outside;
  outside.reserve(reg.polygons.size());
  for (const Polygon& poly : reg.polygons) {
    const std::size_t k = poly.loop.size();
    NodeId worst = kNoNode;
    for (std::size_t i = 0; i < k; ++i) {
      const std::uint32_t u = poly.loop[i], v = poly.loop[(i + 1) % k];
      const Vec3 m = cross(reg.normal, pts_[v] - pts_[u]);  // inward, in the plane
      if (!(length2(m) > 0)) continue;
      NodeId out;
      double scale;
      if (poly.internal[i]) {
        // The line is shared with the neighbouring polygon, which sees it with the other sign:
        // build it once from the lower vertex, oriented the same way for both.
        const bool forward = u < v;
        const NodeId line = sign_form(forward ? u : v, forward ? m : -m, scale);  // inward for `forward`
        const float reach = static_cast<float>(margin_ * scale / length(m));  // margin in the form's units
        out = forward ? g_.binary(Op::Sub, g_.constant(-reach), line) : g_.binary(Op::Sub, line, g_.constant(reach));
      } else {
        out = sign_form(u, -m, scale);
      }
      worst = worst == kNoNode ? out : g_.binary(Op::Max, worst, out);
    }
    if (worst != kNoNode) outside.push_back(worst);
  }
  const NodeId h2 = g_.unary(Op::Square, h);
  if (outside.empty()) return h2;
  const NodeId q = balanced_tree<NodeId>(outside.size(), [&](std::size_t i) { return outside[i]; },
                                         [&](NodeId a, NodeId b) { return g_.binary(Op::Min, a, b); });
  return g_.binary(Op::Max, h2, g_.binary(Op::Mul, q, g_.constant(kGate)));
}

NodeId ExprBuilder::edge_term(const EdgeTerm& e) {
  const Vec3 a = pts_[e.a], b = pts_[e.b];
  // The segment as the f32 endpoints see it: offsets use f32 coordinates.
  const Vec3 af{static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z)};
  const Vec3 bf{static_cast<float>(b.x), static_cast<float>(b.y), static_cast<float>(b.z)};
  const Vec3 d = bf - af;
  const double l2 = length2(d);
  // Both ends round to one f32 point (repair can make vertices closer than floats tell apart):
  // as f32 sees it, the segment is that point.
  if (!(l2 > 0)) return vertex_d2(e.a);
  const auto& pa = offset(e.a);
  // Position along the edge as s = t |d_m| (t in [0, 1] on the segment, d_m d's largest
  // component), so that the step per unit of s, d / |d_m|, is exactly +-1 along axis m.
  const int m = largest_axis(d);
  const double dm = std::fabs(d[m]);
  const NodeId s = linear(e.a, d * (dm / l2));
  const NodeId sc = g_.binary(Op::Max, g_.binary(Op::Min, s, g_.constant(static_cast<float>(dm))), g_.constant(0.0f));
  std::array<NodeId, 3> w;
  if (e.interpolate) {
    // (1 - t) (p - a) + t (p - b): exactly p - a at t = 0 and p - b at t = 1 (s_c / |d_m| is
    // exactly 1 when s_c is clamped to |d_m|).
    const auto& pb = offset(e.b);
    const NodeId t = g_.binary(Op::Div, sc, g_.constant(static_cast<float>(dm)));
    const NodeId t1 = g_.binary(Op::Sub, g_.constant(1.0f), t);
    for (int k = 0; k < 3; ++k)
      w[k] = g_.binary(Op::Add, g_.binary(Op::Mul, t1, pa[k]), g_.binary(Op::Mul, t, pb[k]));
  } else {
    // w = (p - a) - s_c d / |d_m|: exactly p - a at s_c = 0.
    for (int k = 0; k < 3; ++k) {
      const float step = k == m ? (d[m] > 0 ? 1.0f : -1.0f) : static_cast<float>(d[k] / dm);
      if (step == 0.0f) {
        w[k] = pa[k];
      } else if (step == 1.0f || step == -1.0f) {
        w[k] = g_.binary(step > 0 ? Op::Sub : Op::Add, pa[k], sc);
      } else {
        w[k] = g_.binary(Op::Sub, pa[k], g_.binary(Op::Mul, sc, g_.constant(step)));
      }
    }
  }
  return g_.binary(Op::Add, g_.binary(Op::Add, g_.unary(Op::Square, w[0]), g_.unary(Op::Square, w[1])),
                   g_.unary(Op::Square, w[2]));
}

NodeId ExprBuilder::vertex_d2(std::uint32_t v) {
  const auto& o = offset(v);
  // Same association as an edge's |w|^2 at this end, so the unshrunk values would be equal.
  return g_.binary(Op::Add, g_.binary(Op::Add, g_.unary(Op::Square, o[0]), g_.unary(Op::Square, o[1])),
                   g_.unary(Op::Square, o[2]));
}

NodeId ExprBuilder::vertex_term(const VertexTerm& v) {
  return g_.binary(Op::Mul, vertex_d2(v.v), g_.constant(kVertexShrink));
}

NodeId ExprBuilder::vertex_bound(const std::vector<std::uint32_t>& vertices, const Box3& box, double extent) {
  FREP_ASSERT(!vertices.empty(), "a bound without vertices");
  std::vector<Vec3> at(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) at[i] = pts_[vertices[i]];
  const std::vector<std::uint32_t> order = morton_order(at, box);
  const NodeId v = balanced_tree<NodeId>(vertices.size(), [&](std::size_t i) { return vertex_d2(vertices[order[i]]); },
                                         [&](NodeId a, NodeId b) { return g_.binary(Op::Min, a, b); });
  const float slack = static_cast<float>(0x1p-28 * extent * extent);
  return g_.binary(Op::Add, g_.binary(Op::Mul, v, g_.constant(1.0f + 0x1p-8f)), g_.constant(slack));
}

Term ExprBuilder::split(NodeId d2, NodeId sigma, const Vec3& at) {
  // max(d2, -K sigma): d2 where sigma >= 0, at least K |sigma| (far beyond any squared distance
  // except within float-invisible reach of sigma's zero) where sigma < 0; and the mirror.
  return {g_.binary(Op::Max, d2, g_.binary(Op::Mul, sigma, g_.constant(-kGate))),
          g_.binary(Op::Max, d2, g_.binary(Op::Mul, sigma, g_.constant(kGate))), at};
}

Term ExprBuilder::build(const TermSpec& spec, bool signed_terms, const Box3& box) {
  switch (spec.kind) {
    case TermSpec::Edge: {
      const EdgeTerm& e = f_.edges[spec.index];
      const NodeId d2 = edge_term(e);
      if (!signed_terms) return {d2, kNoNode, spec.at};
      // (p - a) . (n1 + n2): the sum of the two planes through the edge, unless the faces are
      // nearly folded onto each other and the sum would cancel to noise: then directly.
      const Vec3 n1 = f_.regions[e.region_a].normal, n2 = f_.regions[e.region_b].normal;
      double scale;
      const NodeId sigma = dot(n1, n2) > -0.5 ? g_.binary(Op::Add, plane(e.region_a), plane(e.region_b))
                                              : sign_form(e.a, n1 + n2, scale);
      return split(d2, sigma, spec.at);
    }
    case TermSpec::Vertex: {
      const VertexTerm& v = f_.vertices[spec.index];
      const NodeId d2 = vertex_term(v);
      if (!signed_terms) return {d2, kNoNode, spec.at};
      double scale;
      return split(d2, sign_form(v.v, v.pseudonormal, scale), spec.at);
    }
    case TermSpec::Cluster: break;
  }
  // A region and its gentle creases: plain min, then the region's sign.
  std::vector<Term> members{{region_term(spec.index), kNoNode, f_.regions[spec.index].center}};
  for (std::uint32_t i : cluster_[spec.index])
    members.push_back({edge_term(f_.edges[i]), kNoNode, (pts_[f_.edges[i].a] + pts_[f_.edges[i].b]) * 0.5});
  NodeId d2;
  if (members.size() == 1) {
    d2 = members[0].d2;
  } else {
    std::vector<Vec3> at(members.size());
    for (std::size_t i = 0; i < members.size(); ++i) at[i] = members[i].at;
    const std::vector<std::uint32_t> order = morton_order(at, box);
    d2 = balanced_tree<NodeId>(members.size(), [&](std::size_t i) { return members[order[i]].d2; },
                               [&](NodeId a, NodeId b) { return g_.binary(Op::Min, a, b); });
  }
  if (!signed_terms) return {d2, kNoNode, spec.at};
  return split(d2, plane(spec.index), spec.at);
}

Term ExprBuilder::distance(bool signed_terms, const Box3& box) {
  // Clusters: with signs, each region takes the gentle creases assigned to it; without signs,
  // every crease stands alone (clusters only exist to share a sign).
  cluster_.assign(f_.regions.size(), {});
  std::vector<TermSpec> specs;
  specs.reserve(f_.regions.size() + f_.edges.size() + f_.vertices.size());
  for (std::uint32_t i = 0; i < f_.edges.size(); ++i) {
    const EdgeTerm& e = f_.edges[i];
    if (signed_terms && e.cluster != MeshTopology::kNone) cluster_[e.cluster].push_back(i);
    else specs.push_back({TermSpec::Edge, i, (pts_[e.a] + pts_[e.b]) * 0.5});
  }
  for (std::uint32_t r = 0; r < f_.regions.size(); ++r) specs.push_back({TermSpec::Cluster, r, f_.regions[r].center});
  for (std::uint32_t i = 0; i < f_.vertices.size(); ++i) specs.push_back({TermSpec::Vertex, i, pts_[f_.vertices[i].v]});
  FREP_ASSERT(!specs.empty(), "a mesh without features");
  std::vector<Vec3> at(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) at[i] = specs[i].at;
  const std::vector<std::uint32_t> order = morton_order(at, box);
  return balanced_tree<Term>(
      specs.size(), [&](std::size_t i) { return build(specs[order[i]], signed_terms, box); },
      [&](const Term& a, const Term& b) { return join(g_, a, b); });
}

std::vector<std::uint32_t> morton_order(const std::vector<Vec3>& points, const Box3& box) {
  const Vec3 size = box.size();
  const double scale[3] = {size.x > 0 ? kMortonCells / size.x : 0, size.y > 0 ? kMortonCells / size.y : 0,
                           size.z > 0 ? kMortonCells / size.z : 0};
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t code = 0;
    for (int k = 0; k < 3; ++k) {
      const double q = std::clamp((points[i][k] - box.lo[k]) * scale[k], 0.0, kMortonCells);
      code |= morton_spread(static_cast<std::uint64_t>(q)) << k;
    }
    keys[i] = {code, static_cast<std::uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

Term join(Graph& g, const Term& a, const Term& b) {
  Term r{g.binary(Op::Min, a.d2, b.d2), kNoNode, a.at};
  if (a.neg != kNoNode) r.neg = g.binary(Op::Min, a.neg, b.neg);
  return r;
}

}  // namespace frep::convert_detail
