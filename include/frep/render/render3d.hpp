// 3D rendering of an expression's surface f = 0 (inside where f < 0) through an orthographic
// camera: a depth map found by interval-pruned column search, refined by bisection, with normals
// from the gradient evaluator. shade.hpp turns the depth map into pictures.
//
// Each pixel's column is sampled at the camera's depth samples from the front; the first sample
// where f < 0 is the hit, and the surface is then located by bisection between it and the sample
// before. Boxes of columns and depth go through the subdivision driver (subdivision.hpp), nearest
// first: boxes whose interval is >= 0 are empty, boxes whose interval is < 0 fill the depth of
// their pixels, boxes behind depths already found are skipped, and the remaining small boxes
// search their columns on a tape simplified for them. The result equals that of sampling every
// column on the full tape (render3d_brute_force), for any thread count and tile sizes.
//
// A model that is one oracle casting rays (a mesh, moved or not: Oracle::casts_rays) is rendered
// by a ray per pixel instead: the exact first hit, cut to the bounds (a ray entering them inside
// the shape shows the face it enters through, or faces the viewer at the front), with the hit
// triangle's normal. It differs from the column search only where samples miss a sliver thinner
// than a depth step, and by at most a step elsewhere.
#pragma once

#include <memory>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"
#include "frep/render/camera.hpp"

namespace frep {

class Subdivider;

struct Render3DOptions {
  int size = 1024;                               // pixels along the longer side of the image (1 to 16384)
  ViewDirection view = ViewDirection::Iso;       // the direction the model is seen from
  bool z_up = false;                             // z is the up axis (CAD models) instead of y (Fidget's models)
  double yaw = 0;                                // degrees added to the view's yaw (about the up axis; 90 turns front into right)
  double pitch = 0;                              // degrees added to the view's pitch (90 turns front into top)
  Box3 bounds{{-1, -1, -1}, {1, 1, 1}};          // the region rendered; the shape is cut at its faces
  int depth_steps = 0;                           // depth cells per column; 0 = cubic voxels (the image's pixel size)
  int refine_steps = 5;                          // bisection steps per hit: depth error <= step / 2^(refine_steps + 1)
  int threads = 0;                               // worker threads; 0 = all hardware threads
  std::vector<int> tiles = {};                   // box edge per subdivision level in voxels, largest first;
                                                 // empty = halving from the volume's size down to 4
  double lipschitz = 0;                          // known bound L on |f(p) - f(q)| / |p - q| (1 for exact distances, as frep convert writes); 0 = unknown
};

// What a 3D render finds: per pixel (row-major, top row first) the depth and normal of the
// nearest surface point in view coordinates (u right, v up, w toward the viewer).
struct DepthMap {
  Camera camera;              // the view; width and height are the image's
  std::vector<float> depth;   // w of the surface point; NaN where the column hits nothing
  std::vector<Vec3f> normal;  // unit normal (the normalized gradient) in view coordinates; (0, 0, 1)
                              // where the column starts inside (the shape cut by the front of the
                              // view volume) or the gradient is zero or not finite; 0 without a hit

  int width() const { return camera.width; }
  int height() const { return camera.height; }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(x); }
  bool hit(int x, int y) const { return depth[index(x, y)] == depth[index(x, y)]; }
};

// Reusable: keeps the subdivision driver's threads and per-worker scratch between frames.
class Renderer3D {
 public:
  explicit Renderer3D(Render3DOptions options = {});
  ~Renderer3D();
  Renderer3D(const Renderer3D&) = delete;
  Renderer3D& operator=(const Renderer3D&) = delete;

  // `tape` is the model's, in model coordinates (any register code state).
  DepthMap render(const Tape& tape);
  const Render3DOptions& options() const { return options_; }
  const Camera& camera() const { return camera_; }

 private:
  struct Worker;
  struct State;

  Render3DOptions options_;
  Camera camera_;
  std::unique_ptr<Subdivider> subdivider_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

// One-shot helper.
DepthMap render3d(const Tape& tape, const Render3DOptions& options = {});

// Reference: searches every column on the full tape (SIMD batches, no pruning, one thread), with
// the same samples and bisection, and the gradient on the full tape. With `row_step` > 1 only
// every row_step-th row is rendered (the others stay empty): rows cost independently, so a
// benchmark can estimate the whole image's cost from a sample.
DepthMap render3d_brute_force(const Tape& tape, const Render3DOptions& options = {}, int row_step = 1);

}  // namespace frep
