// 2D rendering of an expression's sign over [-1, 1]^2: white where the value is negative.
// Pixel centers are at linspace(-1, 1, size) in x and in y, with y = +1 on the top row.
#pragma once

#include <memory>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/render/image.hpp"

namespace frep {

class Subdivider;

struct RenderOptions {
  int size = 1024;                            // image width and height in pixels (1 to 16384)
  int threads = 0;                            // worker threads; 0 = all hardware threads
  float z = 0.0f;                             // the z of the slice for 3D expressions
  std::vector<int> tiles = {256, 64, 16};     // tile edge per subdivision level, largest first;
                                              // the last level is evaluated pixel by pixel (SIMD)
  double lipschitz = 0;                       // known bound L on |f(p) - f(q)| / |p - q| (1 for exact distances, as frep convert writes); 0 = unknown
};

// Tile-recursive renderer: interval arithmetic classifies whole tiles as inside or outside and
// simplifies the tape for each subtile, so small tiles evaluate only their local part. Reusable:
// keeps per-thread evaluators and scratch between frames.
class Renderer2D {
 public:
  explicit Renderer2D(RenderOptions options = {});
  ~Renderer2D();
  Renderer2D(const Renderer2D&) = delete;
  Renderer2D& operator=(const Renderer2D&) = delete;

  Image render(const Tape& tape);
  const RenderOptions& options() const { return options_; }

 private:
  struct Worker;

  RenderOptions options_;
  std::unique_ptr<Subdivider> subdivider_;
  std::vector<std::unique_ptr<Worker>> workers_;  // per worker of the subdivider: pixel scratch
};

// One-shot helper.
Image render2d(const Tape& tape, const RenderOptions& options = {});

// Reference: evaluates every pixel on the full tape (SIMD batches, no pruning, one thread).
Image render2d_brute_force(const Tape& tape, const RenderOptions& options = {});

}  // namespace frep
