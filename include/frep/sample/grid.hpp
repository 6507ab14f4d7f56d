// Dense grids of exact signed distances, from a mesh or from an expression, in one layout:
//
//   samples along each axis at linspace(lo, hi, n), both ends included:
//     x_i = ((n - 1 - i) * lo + i * hi) / (n - 1), i = 0 .. n - 1 (exact at both ends)
//   value[(i * ny + j) * nz + k] = f(x_i, y_j, z_k): C order, z varies fastest, so that NumPy's
//   array[i][j][k] is f(x_i, y_j, z_k).
//
// From a mesh: exact (double precision, rounded once to float32), by the closest point transform
// (scan conversion of each feature's characteristic polyhedron, see docs/sampling.md) for valid
// solids with pseudonormal signs, else by one oracle query per sample. From an expression: the
// pruned evaluator (interval simplification depth first, SIMD batches at the leaves), in float32.
//
// Truncated grids (the `truncate` options, D > 0): every value is clamp(f, -D, D), bit for bit what
// clamping the untruncated grid gives, but only what that needs is computed: the transform scans
// each polyhedron to about D and gives the samples beyond the band their side by a flood fill;
// the expression sampler settles whole boxes whose values all lie beyond +-D. (sample_grid_f64:
// the transform and the oracle queries agree once rounded to float32, not in the last bits of a
// double, and on bounds that cut the mesh a narrow truncated grid comes from the transform where
// the full grid comes from queries.)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"

namespace frep {

class MeshField;

struct GridSpec {
  Box3 bounds;                      // the corner samples are bounds.lo and bounds.hi
  std::array<int, 3> counts{0, 0, 0};  // samples per axis (x, y, z), each >= 2

  // Coordinate of sample i along `axis` (formula above).
  double coord(int axis, int i) const;
  std::size_t size() const {
    return static_cast<std::size_t>(counts[0]) * static_cast<std::size_t>(counts[1]) * static_cast<std::size_t>(counts[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * static_cast<std::size_t>(counts[1]) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(counts[2]) + static_cast<std::size_t>(k);
  }
  // Throws InputError unless every count is in [2, 4096], the bounds are finite and lo < hi on
  // every axis.
  void check() const;
};

// A cube grid of n^3 samples over `bounds`.
GridSpec cube_grid(const Box3& bounds, int n);

// Default bounds for a mesh: the cube around its bounding box's centre whose side is the box's
// largest extent plus twice `margin` times its diagonal (so cube grids have cubic voxels).
Box3 default_mesh_bounds(const Box3& mesh_box, double margin = 0.05);

enum class MeshGridMethod {
  Auto,     // closest point transform where it is exact (solid, pseudonormal sign), else Queries
  Cpt,      // closest point transform (InputError if the mesh is not a solid with pseudonormal signs)
  Queries,  // one MeshDistance query per sample (any mesh, any sign method)
};

struct MeshGridOptions {
  MeshGridMethod method = MeshGridMethod::Auto;
  int threads = 0;  // 0: all cores
  double truncate = 0;  // D > 0: values clamped to [-D, D], exact within D of the surface (Queries: each sample clamped); 0: off
  // Called now and then with a stage name and the fraction of the whole job done (0 to 1).
  std::function<void(const char* stage, double fraction)> progress;
};

struct MeshGridStats {
  MeshGridMethod method = MeshGridMethod::Queries;  // the one that ran
  std::size_t features = 0;        // CPT: characteristic polyhedra scanned (faces count twice, once in narrow truncated grids)
  std::uint64_t evaluations = 0;   // CPT: feature distances computed at grid samples
  std::size_t fallback_samples = 0;  // CPT: samples no polyhedron reached, answered by the oracle (0 expected)
  std::size_t band_samples = 0;      // CPT, truncated: samples computed exactly (the rest got +-D by their side)
  std::size_t side_queries = 0;      // CPT, truncated: oracle queries for a side (1 for a grid the surface misses, else 0)
  double seconds = 0;
};

// Exact signed distances of `field` at every sample of `grid` (layout above).
std::vector<float> sample_grid(const MeshField& field, const GridSpec& grid, const MeshGridOptions& options = {},
                               MeshGridStats* stats = nullptr);
// The same in double precision (for tests and callers that need the unrounded values).
std::vector<double> sample_grid_f64(const MeshField& field, const GridSpec& grid,
                                    const MeshGridOptions& options = {}, MeshGridStats* stats = nullptr);

struct ExprGridOptions {
  int threads = 0;                         // 0: all cores
  std::vector<int> tiles = {64, 16, 4};    // subdivision levels, box edge in samples (largest first)
  double truncate = 0;                     // D > 0: values clamped to [-D, D]; boxes entirely beyond +-D are filled unevaluated; 0: off
  double lipschitz = 0;                    // with truncate: a bound L on |f(p) - f(q)| / |p - q| (FieldInfo::lipschitz) also
                                           // settles boxes whose centre value is beyond D + L r; 0: unknown
};

// f(x_i, y_j, z_k) of a compiled expression (register code: Tape::compile) at every sample, with
// coordinates rounded to float32; values are bit-identical to BatchEvaluator on the full tape
// (clamped to +-truncate when asked).
std::vector<float> sample_grid(const Tape& tape, const GridSpec& grid, const ExprGridOptions& options = {});

}  // namespace frep
