// The features of a closed mesh that the distance expression is made of (private to the
// converter): flat regions split into convex polygons, crease edges, and the vertices that need
// a term of their own. Decided exactly (edge shapes come from exact orientation predicates).
#pragma once

#include <cstdint>
#include <vector>

#include "frep/math/vec.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/topology.hpp"

namespace frep::convert_detail {

// A convex polygon of a flat region, counter-clockwise about the region's outward normal. Edge i
// runs from loop[i] to loop[i + 1]; `internal[i]` marks edges inside the region (shared with
// another polygon of it), whose prism test is widened by a small margin so that the region's
// prism has no cracks in floating point.
struct Polygon {
  std::vector<std::uint32_t> loop;
  std::vector<char> internal;
};

// Coplanar neighbouring triangles (joined through flat edges): one plane term.
struct Region {
  Vec3 normal;             // unit, outward
  std::uint32_t anchor;    // a vertex of the region: the plane is (p - anchor) . normal
  Vec3 center;             // area-weighted centroid, for spatial ordering
  std::vector<Polygon> polygons;
  std::size_t triangles = 0;
};

// A crease edge: its segment's distance covers its endpoints too. The segment is computed from
// `a` (exact at a's end); with `interpolate`, it is computed so it is exact at both ends (needed
// when both endpoints have vertex terms that must win ties there). A gentle crease joins the
// cluster of one of its regions and takes that region's sign (right throughout the edge's
// Voronoi region when the normals are less than ~84 degrees apart); a sharp one carries its
// own sign, from its pseudonormal n1 + n2.
struct EdgeTerm {
  std::uint32_t a, b;
  std::uint32_t region_a, region_b;  // the regions on its two sides
  std::uint32_t cluster;             // the region whose sign it takes, or kNone: its own sign
  bool interpolate;
};

// A vertex whose Voronoi region is not empty and in which the signs of the edges that reach it
// could be wrong: it gets its own distance term, signed by its angle-weighted pseudonormal.
struct VertexTerm {
  std::uint32_t v;
  Vec3 pseudonormal;
};

struct Features {
  std::vector<Region> regions;
  std::vector<EdgeTerm> edges;
  std::vector<VertexTerm> vertices;
  std::vector<std::uint32_t> region_of;  // per triangle (kNone for collapsed triangles)
};

// Extracts the features of a welded, validated closed mesh (every usable edge manifold and
// consistent; no zero-area triangles).
Features extract_features(const TriMesh& welded, const MeshTopology& topology);

}  // namespace frep::convert_detail
