// Shared helpers for the mesher tests: every mesh a test produces goes through the validator
// behind `frep check` (closed, manifold, no pinched vertices, outward, no self-intersections).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "frep/contour/mesher.hpp"
#include "frep/expr/model.hpp"
#include "frep/mesh/validate.hpp"

namespace frep::test {

// Checks that `m` is a valid solid (or, with allow_empty, possibly empty); returns the report.
inline ValidationReport expect_solid(const TriMesh& m, const std::string& what) {
  ValidationReport r = validate_mesh(m);
  EXPECT_TRUE(r.is_solid()) << what << ": " << r.to_text();
  for (const Vec3& v : m.vertices) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
      ADD_FAILURE() << what << ": non-finite vertex";
      break;
    }
    // f32 coordinates: what STL stores, so the checks hold for STL files too. (Through a
    // volatile: GCC 12's SLP vectorizer may drop a (double)(float) round trip.)
    auto is_f32 = [](double d) {
      volatile float f = static_cast<float>(d);
      return static_cast<double>(f) == d;
    };
    if (!is_f32(v.x) || !is_f32(v.y) || !is_f32(v.z)) {
      ADD_FAILURE() << what << ": a coordinate is not an f32 value: vertex " << (&v - m.vertices.data()) << " of " << m.vertices.size() << " " << v.x << " " << v.y << " " << v.z;
      break;
    }
  }
  return r;
}

// Meshes and validates in one go.
inline TriMesh mesh_solid(const Tape& tape, const MeshOptions& o, const std::string& what, MeshStats* stats = nullptr) {
  MeshStats st;
  TriMesh m = mesh_expression(tape, o, &st);
  expect_solid(m, what);
  EXPECT_EQ(st.unresolved, 0u) << what;
  EXPECT_EQ(st.triangles, m.triangles.size());
  if (stats) *stats = st;
  return m;
}
inline TriMesh mesh_solid(Expr e, const MeshOptions& o, const std::string& what, MeshStats* stats = nullptr) {
  return mesh_solid(Tape::compile(e.graph(), e.id()), o, what, stats);
}

// Options for meshing a loaded model as `frep mesh` does: its box and Lipschitz bound.
inline MeshOptions model_options(const Model& m, int resolution) {
  MeshOptions o;
  o.resolution = resolution;
  o.known_bounds = m.info.bounds;
  o.lipschitz = m.info.lipschitz;
  return o;
}

inline MeshOptions options(int resolution, Box3 bounds = Box3{{-1, -1, -1}, {1, 1, 1}},
                           MeshMethod method = MeshMethod::DualContouring) {
  MeshOptions o;
  o.resolution = resolution;
  o.bounds = bounds;
  o.method = method;
  return o;
}

}  // namespace frep::test
