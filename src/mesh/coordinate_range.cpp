// The rule of what frep can represent of a mesh's coordinates (see coordinate_range.hpp).
#include "frep/mesh/coordinate_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frep/error.hpp"

namespace frep {
namespace {

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

// "vertex 3 (a corner of triangle 1, line 6) at (0, 0, 1e+30)".
std::string describe_vertex(const TriMesh& m, std::uint32_t v, std::uint32_t t) {
  std::string s = "vertex " + std::to_string(v);
  if (t != CoordinateSpan::kNone) {
    s += " (a corner of triangle " + std::to_string(t);
    if (const FaceOrigin o = m.origin_of(t); o.line) s += ", line " + std::to_string(o.line);
    s += ")";
  }
  const Vec3& p = m.vertices[v];
  return s + " at (" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")";
}

bool valid_triangle(const TriMesh& m, const Triangle& t) {
  return t[0] < m.vertices.size() && t[1] < m.vertices.size() && t[2] < m.vertices.size();
}

}  // namespace

CoordinateSpan measure_coordinate_span(const TriMesh& m) {
  CoordinateSpan s;
  const std::size_t nt = m.triangles.size();
  Box3 box;
  std::vector<double> shortest;
  shortest.reserve(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = m.triangles[t];
    if (!valid_triangle(m, tri)) continue;
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.vertices[tri[k]];
      for (int c = 0; c < 3; ++c) {
        const double a = std::fabs(p[c]);
        if (!(a < kFloatRangeLimit)) {
          finite = false;
          if (s.out_of_range_vertex == CoordinateSpan::kNone)
            s.out_of_range_vertex = tri[k], s.out_of_range_triangle = static_cast<std::uint32_t>(t);
        } else {
          s.largest_coordinate = std::max(s.largest_coordinate, a);
        }
      }
      if (finite) box.add(p);
    }
    if (!finite) continue;
    const Vec3 &a = m.vertices[tri[0]], &b = m.vertices[tri[1]], &c = m.vertices[tri[2]];
    const double e = std::min({length(b - a), length(c - b), length(a - c)});
    if (e > 0) shortest.push_back(e);
  }
  if (!box.empty()) s.diagonal = length(box.size());
  if (!shortest.empty()) {
    auto mid = shortest.begin() + static_cast<std::ptrdiff_t>(shortest.size() / 2);
    std::nth_element(shortest.begin(), mid, shortest.end());
    s.median_shortest_edge = *mid;
  }
  if (nt == 0) return s;
  // The median point of the corners (of at most 2^16 evenly spaced triangles), and the corner
  // farthest from it on some axis.
  const std::size_t step = std::max<std::size_t>(1, nt / 65536);
  std::vector<double> axis;
  Vec3 median;
  for (int c = 0; c < 3; ++c) {
    axis.clear();
    for (std::size_t t = 0; t < nt; t += step) {
      const Triangle& tri = m.triangles[t];
      if (!valid_triangle(m, tri)) continue;
      for (std::uint32_t v : tri)
        if (std::fabs(m.vertices[v][c]) < kFloatRangeLimit) axis.push_back(m.vertices[v][c]);
    }
    if (axis.empty()) return s;
    auto mid = axis.begin() + static_cast<std::ptrdiff_t>(axis.size() / 2);
    std::nth_element(axis.begin(), mid, axis.end());
    median[c] = *mid;
  }
  double far = -1;
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = m.triangles[t];
    if (!valid_triangle(m, tri)) continue;
    for (std::uint32_t v : tri) {
      const Vec3& p = m.vertices[v];
      const double d = std::max({std::fabs(p.x - median.x), std::fabs(p.y - median.y), std::fabs(p.z - median.z)});
      if (d > far) far = d, s.far_vertex = v, s.far_triangle = static_cast<std::uint32_t>(t);
    }
  }
  return s;
}

void check_coordinate_range(const TriMesh& m) {
  const CoordinateSpan s = measure_coordinate_span(m);
  if (s.out_of_range_vertex != CoordinateSpan::kNone) {
    const Vec3& p = m.vertices[s.out_of_range_vertex];
    const bool nan = std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z);
    throw InputError(m.name, 0,
                     describe_vertex(m, s.out_of_range_vertex, s.out_of_range_triangle) +
                         (nan ? " has a coordinate that is not a number"
                              : " lies beyond the range of 32-bit floats (+-3.4e38), in which frep takes points "
                                "and writes distances"));
  }
  if (s.median_shortest_edge > 0 && s.median_shortest_edge < kFloatSpanRatio * s.diagonal &&
      s.far_vertex != CoordinateSpan::kNone)
    throw InputError(m.name, 0,
                     "the mesh spans more than 32-bit floats can carry: " +
                         describe_vertex(m, s.far_vertex, s.far_triangle) + " makes it " + number(s.diagonal) +
                         " across, but half of its triangles have an edge shorter than " +
                         number(s.median_shortest_edge) + ", below 2^-20 of that size (" +
                         number(kFloatSpanRatio * s.diagonal) +
                         "), about what floats resolve there: its distances would be wrong. Is that vertex a stray?");
}

}  // namespace frep
