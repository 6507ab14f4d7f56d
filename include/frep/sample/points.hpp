// Point samples with signed distances, the training data of neural SDFs: rows (x, y, z, d) of
// float32, either uniform in a box or near the surface (surface points plus isotropic Gaussian
// noise). Reproducible: point i depends only on the seed and i (a counter-based generator), not
// on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"

namespace frep {

class MeshField;

struct PointSampleOptions {
  std::uint64_t seed = 0;
  int threads = 0;  // 0: all cores
};

// `count` rows (x, y, z, d), flattened: row r is out[4 r .. 4 r + 3]. Coordinates are rounded to
// float32 first and the distance is that of the rounded point.
//
// Uniform in `bounds`; from a mesh, d is exact (MeshField::signed_distance).
std::vector<float> sample_uniform(const MeshField& field, const Box3& bounds, std::size_t count,
                                  const PointSampleOptions& options = {});
// Near the surface: points uniform on the surface (triangles chosen by area) moved by Gaussian
// noise of standard deviation `sigma` on each axis.
std::vector<float> sample_near_surface(const MeshField& field, std::size_t count, double sigma,
                                       const PointSampleOptions& options = {});

// The same from an expression (a tape with register code), evaluated in float32.
std::vector<float> sample_uniform(const Tape& tape, const Box3& bounds, std::size_t count,
                                  const PointSampleOptions& options = {});
// Surface points: uniform points of `bounds` projected onto f = 0 by Newton steps along the
// gradient (p -= f grad f / |grad f|^2); those that converge (|f| below 1e-6 of the bounds'
// diagonal within 16 steps) and stay in the bounds are kept, until there are `count`. Then
// Gaussian noise as above. Throws InputError if too few points converge (no surface in the bounds).
std::vector<float> sample_near_surface(const Tape& tape, const Box3& bounds, std::size_t count, double sigma,
                                       const PointSampleOptions& options = {});

}  // namespace frep
