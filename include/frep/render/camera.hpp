// The orthographic camera of the 3D renderer: the direction a box of space is seen from, and the
// grid of pixels and depth samples that covers it. By default y is up (as in Fidget's models) and
// the front view looks from +z, showing x to the right; with z up (CAD and 3D-printing models)
// the front view looks from -y, showing x to the right and z up, and the top view looks from +z.
#pragma once

#include <string>
#include <vector>

#include "frep/math/vec.hpp"

namespace frep {

// Named directions to look from; each is a yaw and a pitch (view_angles).
enum class ViewDirection { Iso, Front, Back, Left, Right, Top, Bottom };

// "iso", "front", "back", "left", "right", "top", "bottom"; false for anything else.
bool parse_view_direction(const std::string& name, ViewDirection& out);
const char* view_direction_name(ViewDirection view);
// The view's yaw (degrees about the up axis, 90 = from +x) and pitch (degrees, 90 = from above,
// looking down). Iso is yaw 45, pitch 35.26: from the direction (1, 1, 1) with y up, (1, -1, 1)
// with z up.
void view_angles(ViewDirection view, double& yaw, double& pitch);

// An orthographic view: view coordinates (u right, v up, w toward the viewer) have their origin
// at `center`; the view volume |u| <= half_u, |v| <= half_v, |w| <= half_w encloses the box
// given to make_camera. Pixels are square cells of the (u, v) rectangle, `width` by `height`;
// each pixel's column is sampled at depth + 1 values of w from +half_w (nearest) to -half_w.
struct Camera {
  Vec3 center{0, 0, 0};                                  // model point at view coordinates (0, 0, 0)
  Vec3 right{1, 0, 0}, up{0, 1, 0}, toward{0, 0, 1};     // model directions of u, v and w (orthonormal)
  double half_u = 1, half_v = 1, half_w = 1;             // half extents of the view volume
  int width = 1, height = 1;                             // image size in pixels
  int depth = 1;                                         // depth cells (samples per column minus one)
  bool axis_aligned = true;                              // u, v, w are model axes up to sign: the volume is the box

  // The model point at view coordinates (u, v, w).
  Vec3 to_model(double u, double v, double w) const { return center + right * u + up * v + toward * w; }
  // Pixel edges along u (width + 1 values, increasing), along v (height + 1, top row first, so
  // decreasing) and depth samples along w (depth + 1, nearest first, so decreasing), in f32 as
  // the renderer evaluates them.
  std::vector<float> u_edges() const;
  std::vector<float> v_edges() const;
  std::vector<float> w_samples() const;
  // Pixel centers: the midpoints of consecutive edges, in f32.
  static std::vector<float> centers(const std::vector<float>& edges);
};

// The camera looking at `bounds` from (yaw, pitch) in degrees (yaw about the up axis), with
// `size` pixels along the longer side of the image and `depth_steps` depth cells (0: cubic
// voxels); `z_up` chooses z rather than y as the up axis. Entries of the rotation within 1e-12
// of 0 or +-1 are snapped, so that the named views are exact.
Camera make_camera(const Box3& bounds, double yaw_degrees, double pitch_degrees, int size, int depth_steps = 0,
                   bool z_up = false);

// Square pixels for a rectangle of extents (a, b) with `size` pixels along the longer side:
// the pixel counts along a and b (each at least 1, the longer exactly `size`).
void fit_pixels(double a, double b, int size, int& count_a, int& count_b);

}  // namespace frep
