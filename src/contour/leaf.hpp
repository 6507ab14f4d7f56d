// One subdivision leaf of the mesher: sample its cell corners, find the surface cells, their
// crossings and dual vertices, and keep what the assembly needs to join cells into polygons.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contour/mesh_grid.hpp"
#include "frep/contour/mesh_options.hpp"
#include "frep/contour/snap.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"

namespace frep::contour {

inline constexpr std::uint16_t kNoCell = 0xffff;
// Dual vertices stay this far (in cells) inside their cell: vertices of different cells never
// coincide, even where the QEF minimizer or the surface lies on a cell face.
inline constexpr double kVertexInset = 1e-4;

// v rounded to the nearest f32, through a volatile: GCC 12.2's SLP vectorizer drops the
// rounding of (double)(float) on fields of a struct of doubles at -O2 (x and y of a Vec3 came
// out unrounded; reproduced in isolation), so a plain cast cannot be trusted here.
inline double round_f32(double v) {
  volatile float f = static_cast<float>(v);
  return f;
}
inline Vec3 round_f32(const Vec3& p) { return {round_f32(p.x), round_f32(p.y), round_f32(p.z)}; }

// p rounded to f32 coordinates (what STL stores, so every check on the mesh holds for the file
// too), kept inside `box`: a coordinate that rounds out of it steps back in, one f32 at a time.
inline Vec3 to_f32_inside(const Vec3& p, const Box3& box) {
  Vec3 r;
  for (int a = 0; a < 3; ++a) {
    double v = round_f32(std::clamp(p[a], box.lo[a], box.hi[a]));
    const float mid = static_cast<float>(0.5 * (box.lo[a] + box.hi[a]));
    for (int i = 0; i < 4 && (v < box.lo[a] || v > box.hi[a]); ++i) v = std::nextafter(static_cast<float>(v), mid);
    r[a] = v;
  }
  return r;
}

// A cell with sign changes.
struct SurfaceCell {
  std::uint32_t first_vertex = 0;  // index of its first dual vertex in the leaf
  std::uint8_t config = 0;         // bit c: corner c inside
  std::uint8_t decisions = 0;      // per ambiguous face: inside joined across it
  // Crossing on the edges at the cell's low corner along x, y, z (the edges the cell owns in
  // the assembly), as a fraction of the edge; NaN without a crossing.
  float t[3] = {};
};

struct LeafRecord {
  IndexBox box;
  std::uint64_t key = 0;                 // leaf position in leaf-size units, z-major
  std::vector<std::uint16_t> cell_slot;  // per cell of the box: index into `cells`, or kNoCell
  std::vector<SurfaceCell> cells;
  std::vector<Vec3> positions;           // dual vertices
  std::vector<Vec3f> normals;            // unit, or zero where unknown
  std::vector<Vec3> mass;                // per vertex: its crossings' centroid, inside the cell (a safe fallback)
  std::vector<std::uint8_t> piece;       // per vertex: index among its cell's vertices, and (high nibble) their count
  bool touches_cap = false;              // a boundary corner of the grid is inside the shape
  // Filled by the assembly.
  std::uint32_t vertex_offset = 0;
};

// Per worker: evaluators and scratch for processing leaves.
class LeafMesher {
 public:
  // `cut`: the box the field is closed at (see close_at_box).
  LeafMesher(const MeshGrid& grid, const Box3& cut, const MeshOptions& options) : grid_(grid), cut_(cut), o_(options) {}
  // Processes one leaf box with its simplified tape; returns false (record untouched but for
  // the scratch) if no cell in it has a sign change.
  bool process(const Tape& tape, const IndexBox& box, LeafRecord& out);
  // Corners inside the grid (not on its boundary) where the field was exactly 0, next to another
  // such corner along a cell edge, over every call.
  std::uint64_t zero_corners() const { return zero_corners_; }

 private:
  struct Crossing {
    std::uint32_t corner;  // low end (leaf corner index)
    std::uint8_t axis;
    float t;               // along the edge from the low end
    Vec3 p;                // position
    Vec3f n;               // unit normal, or zero
  };
  // Fills values_ at the leaf's corners (xs_, ys_, zs_ hold their positions).
  void sample_corners(const Tape& tape);
  void find_roots(const Tape& tape);
  void find_normals(const Tape& tape);
  void place_vertices_dc(const Tape& tape, LeafRecord& out);
  // Moves the vertices of smooth cells onto the surface (place_vertices_dc).
  void project_smooth_vertices(const Tape& tape, LeafRecord& out);
  void place_vertices_snap(const Tape& tape, LeafRecord& out);

  const MeshGrid& grid_;
  Box3 cut_;
  const MeshOptions& o_;
  std::uint64_t zero_corners_ = 0;
  BatchEvaluator batch_;
  GradEvaluator grad_;
  SurfaceSnapper snapper_;
  // Leaf geometry of the current call. Corners are numbered x + cx_ (y + cy_ z) in the leaf.
  IndexBox box_;
  int ex_ = 0, ey_ = 0, ez_ = 0;  // cells per axis
  int cx_ = 0, cy_ = 0, cz_ = 0;  // corners per axis (cells + 1)
  std::size_t stride_[3] = {};    // corner index step along each axis
  std::size_t off_[8] = {};       // corner index of a cell's corner c relative to its corner 0
  // Grid indices of leaf corner k, and its position.
  std::array<int, 3> grid_index(std::size_t k) const {
    return {box_.lo[0] + static_cast<int>(k % stride_[1]),
            box_.lo[1] + static_cast<int>((k / stride_[1]) % static_cast<std::size_t>(cy_)),
            box_.lo[2] + static_cast<int>(k / stride_[2])};
  }
  Vec3 corner_position(std::size_t k) const {
    const auto g = grid_index(k);
    return {grid_.coord(0, g[0]), grid_.coord(1, g[1]), grid_.coord(2, g[2])};
  }
  // The crossing on edge e of the cell whose corner 0 is leaf corner `base`.
  const Crossing& crossing(std::size_t base, int e) const;
  std::vector<float> xs_, ys_, zs_, values_;
  std::vector<std::uint8_t> known_;           // per corner: its value is set (sample_corners)
  std::vector<std::uint32_t> pending_;        // corners to evaluate in the current round
  std::vector<float> px_, py_, pz_, pv_;      // their positions and values
  std::vector<std::int32_t> edge_slot_[3];  // per corner: crossing of the edge along axis a, or -1
  std::vector<Crossing> crossings_;
  std::vector<std::uint32_t> cell_index_;   // leaf cell index per surface cell of `out`
  // Root finding state per crossing.
  std::vector<float> t_in_, f_in_, t_out_, f_out_;
  std::vector<std::uint32_t> retry_;  // crossings whose normal is taken again (find_normals)
  std::vector<std::int8_t> last_side_;  // the side the last points fell on, counted (-k: k inside in a row)
  std::vector<float> proposal_, f_eval_;
  std::vector<float> cap_x_, cap_y_, cap_z_, cap_v_;
  std::vector<std::uint32_t> active_;
  std::vector<Grad> grads_;
  std::vector<Grad> root_grad_;              // per crossing: the gradient where root finding accepted it
  std::vector<std::uint8_t> has_root_grad_;  // (find_roots, with oracles in the tape)
  std::vector<Box3> keep_in_;
  std::vector<std::uint32_t> smooth_;   // vertices to project (project_smooth_vertices)
};

}  // namespace frep::contour
