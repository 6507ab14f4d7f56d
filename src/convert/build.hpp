// Building the distance expression from a mesh's features (private to the converter).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "convert/features.hpp"
#include "frep/expr/graph.hpp"
#include "frep/mesh/mesh.hpp"

namespace frep::convert_detail {

// A squared distance term. Unsigned: `d2`. Signed: the term split by the sign of its feature's
// pseudonormal test sigma (on the feature's own Voronoi region, sigma > 0 outside the solid):
// `d2` is its squared distance where sigma >= 0 and huge elsewhere (it counts towards the nearest
// outside feature, P), `neg` the same where sigma <= 0 (towards the nearest inside feature, N).
// The distance is sqrt(P) where P <= N and -sqrt(N) elsewhere; deep inside or outside, intervals
// then settle the sign, and pruning drops either side's features independently.
struct Term {
  NodeId d2;
  NodeId neg = kNoNode;
  Vec3 at;
};

// The coordinates the expression works in: (x - origin) * scale. Moving a mesh far from the
// origin next to it keeps the f32 offsets p - v precise (a part at x = 1000 would otherwise lose
// bits to the 1000); scaling by a power of two keeps squared distances of huge or tiny meshes
// within f32's range. Both are exact for query points near the mesh.
struct Frame {
  Vec3f origin{0, 0, 0};
  float scale = 1.0f;
};

// A term not built yet: which feature, and where it is.
struct TermSpec {
  enum Kind : std::uint8_t { Cluster, Edge, Vertex } kind;
  std::uint32_t index;  // region (Cluster), into Features::edges, into Features::vertices
  Vec3 at;
};

// Writes the expression's nodes into a graph, sharing what features share: the offsets p - v
// of each vertex, each region's plane, each internal polygon edge's line.
class ExprBuilder {
 public:
  // `points`: the mesh's vertices (features refer to them by index), possibly followed by more
  // points (TetGen's), in the frame's coordinates (see Frame). `margin`: how far (in those
  // units) prism tests reach past internal polygon edges.
  ExprBuilder(Graph& g, const std::vector<Vec3>& points, const Features& features, double margin,
              const Frame& frame = {});

  // The whole distance: every feature's term, combined in a balanced tree over the features'
  // Morton order (gentle creases first join their region's cluster: plain min, one sign). Nodes
  // are created in the tree's post-order, so that the tape evaluates one subtree after another
  // and few values are live at once. With `signed_terms`, the result is split into P and N (see
  // Term).
  Term distance(bool signed_terms, const Box3& box);

  // min over `vertices` of |p - v|^2, grown by 2^-8 of itself plus (2^-14 extent)^2: an upper
  // bound of the squared distance (the vertices lie on the surface) that stays above the computed
  // distance despite its roundings (near a vertex, the terms of its edges or of the flat region
  // around it compute |p - v|^2 with an error below 2^-20 of itself plus 2^-30 extent^2). Its
  // interval over a box is tight, so min(P, bound) lets interval pruning drop every term that
  // starts beyond it (see eval/caps.hpp). `extent` bounds the vertices' coordinates.
  NodeId vertex_bound(const std::vector<std::uint32_t>& vertices, const Box3& box, double extent);

  // The plane value (p - anchor) . normal of a region: negative behind (inside) it.
  NodeId plane(std::uint32_t region);
  // (p - v) . c for a point v and a coefficient vector c.
  NodeId linear(std::uint32_t v, const Vec3& c);
  // (p - v) . c / |c_m| (c_m the largest component): the same sign, one multiplication fewer.
  // `scale` receives |c_m|.
  NodeId sign_form(std::uint32_t v, const Vec3& c, double& scale);
  NodeId constant(double v) { return g_.constant(static_cast<float>(v)); }
  const Vec3& point(std::uint32_t i) const { return pts_[i]; }
  Graph& graph() { return g_; }
  // The frame's coordinate nodes.
  std::array<NodeId, 3> coords() const { return {x_, y_, z_}; }

 private:
  const std::array<NodeId, 3>& offset(std::uint32_t v);
  NodeId region_term(std::uint32_t r);
  NodeId edge_term(const EdgeTerm& e);
  NodeId vertex_term(const VertexTerm& v);
  NodeId vertex_d2(std::uint32_t v);
  Term build(const TermSpec& spec, bool signed_terms, const Box3& box);
  // A signed term from its squared distance and its sign test (see Term).
  Term split(NodeId d2, NodeId sigma, const Vec3& at);

  Graph& g_;
  const std::vector<Vec3>& pts_;
  const Features& f_;
  double margin_;
  NodeId x_, y_, z_;
  std::vector<std::array<NodeId, 3>> offset_;  // per point, kNoNode until used
  std::vector<NodeId> plane_;                  // per region
  std::vector<std::vector<std::uint32_t>> cluster_;  // per region: the creases that take its sign
};

// Joins two terms: the minimum of the squared distances (of P and of N for signed terms).
Term join(Graph& g, const Term& a, const Term& b);

// Morton order of points within a box (for spatially balanced trees).
std::vector<std::uint32_t> morton_order(const std::vector<Vec3>& points, const Box3& box);

// A balanced binary tree over items [0, n): leaf(i) makes item i, join(a, b) two subtrees. Built
// depth first (left subtree, right subtree, join), so whatever leaf() and join() create comes in
// post-order; the recursion depth is log2(n).
template <class T, class Leaf, class Join>
T balanced_tree(std::size_t n, Leaf&& leaf, Join&& join) {
  auto build = [&](auto&& self, std::size_t lo, std::size_t hi) -> T {
    if (hi - lo == 1) return leaf(lo);
    const std::size_t mid = lo + (hi - lo) / 2;
    T a = self(self, lo, mid);
    T b = self(self, mid, hi);
    return join(a, b);
  };
  return build(build, 0, n);
}

}  // namespace frep::convert_detail
