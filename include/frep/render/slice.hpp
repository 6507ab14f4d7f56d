// 2D slices of an expression on an axis plane, coloured so that one sees whether the field is a
// distance: inside (f < 0) and outside in two colours that darken with |f| (flat between contour
// lines), thin contour lines every `contour` units of f and a bold line on f = 0. Lines are drawn
// at a constant width in pixels (the distance to a contour is estimated as |f - k n| / |in-plane
// gradient|, where a neighbouring pixel lies across it), so for a signed distance they are
// evenly spaced, and where they crowd or spread the field is not one; where they would be closer
// than 5 pixels they fade out.
#pragma once

#include <memory>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"
#include "frep/render/image.hpp"

namespace frep {

class Subdivider;

struct SliceOptions {
  int size = 1024;                          // pixels along the longer side of the picture (1 to 16384)
  int axis = 2;                             // the plane's normal: 0 = x, 1 = y, 2 = z
  float offset = 0;                         // the plane is {coordinate `axis` = offset}
  Box3 bounds{{-1, -1, -1}, {1, 1, 1}};     // the picture covers the other two axes' ranges
  double contour = 0;                       // contour spacing in units of f; 0 = default_contour_spacing
  int threads = 0;                          // worker threads; 0 = all hardware threads
  std::vector<int> tiles = {256, 64, 16};   // tile edge per subdivision level, largest first
};

// The image axes of a slice: z = c shows (x right, y up), y = c shows (x, z), x = c shows (y, z).
int slice_right_axis(int axis);
int slice_up_axis(int axis);

// The field sampled on a slice, at pixel centers (row-major, top row first).
struct SliceField {
  int width = 0, height = 0;
  int axis = 2;                    // the plane's normal axis
  double pixel = 0;                // model units per pixel
  std::vector<float> right, up;    // coordinates of the pixel centers along the image axes (up: top row first)
  std::vector<float> value;        // f
  std::vector<float> slope;        // length of f's gradient within the plane
};

// Reusable: keeps the subdivision driver's threads and per-worker scratch between slices.
class SliceRenderer {
 public:
  explicit SliceRenderer(SliceOptions options = {});
  ~SliceRenderer();
  SliceRenderer(const SliceRenderer&) = delete;
  SliceRenderer& operator=(const SliceRenderer&) = delete;

  // The field on the slice: tiles are pruned by interval arithmetic and evaluated on their own
  // simplified tape, so values equal those of the full tape at every pixel.
  SliceField field(const Tape& tape);
  // The coloured picture (RGB).
  Image render(const Tape& tape);
  const SliceOptions& options() const { return options_; }

 private:
  struct Worker;

  SliceOptions options_;
  std::unique_ptr<Subdivider> subdivider_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

// One-shot helper.
Image render_slice(const Tape& tape, const SliceOptions& options = {});

// The default contour spacing for a picture whose longer side spans `extent` model units: the
// largest of 1, 2, 5 times a power of ten that is at most extent / 10.
double default_contour_spacing(double extent);

// Colours of the picture.
struct SliceColours {
  static constexpr std::uint8_t inside[3] = {72, 132, 204};   // f < 0, next to the surface
  static constexpr std::uint8_t outside[3] = {232, 150, 76};  // f >= 0, next to the surface
  static constexpr std::uint8_t zero[3] = {255, 255, 255};    // the bold line f = 0
  static constexpr std::uint8_t nan[3] = {128, 128, 128};     // f is NaN
  static constexpr float line_darkening = 0.55f;              // contour lines: the colour times this
  static constexpr float zero_half_width = 1.5f;              // pixels
  static constexpr float line_half_width = 0.6f;              // pixels
};

// Colours a sampled slice with contours every `contour` units (> 0).
Image colour_slice(const SliceField& field, double contour);

}  // namespace frep
