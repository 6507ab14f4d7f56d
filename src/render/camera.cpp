// The orthographic camera: named views, the rotation from yaw and pitch, and the pixel grid.
#include "frep/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "frep/error.hpp"

namespace frep {
namespace {

struct NamedView {
  ViewDirection view;
  const char* name;
  double yaw, pitch;
};
// Iso looks from (1, 1, 1): pitch = atan(1 / sqrt(2)).
constexpr double kIsoPitch = 35.264389682754654;
constexpr NamedView kViews[] = {
    {ViewDirection::Iso, "iso", 45, kIsoPitch}, {ViewDirection::Front, "front", 0, 0},
    {ViewDirection::Back, "back", 180, 0},      {ViewDirection::Left, "left", -90, 0},
    {ViewDirection::Right, "right", 90, 0},     {ViewDirection::Top, "top", 0, 90},
    {ViewDirection::Bottom, "bottom", 0, -90},
};

double snap(double v) {
  if (std::fabs(v) < 1e-12) return 0;
  if (std::fabs(std::fabs(v) - 1) < 1e-12) return v > 0 ? 1 : -1;
  return v;
}
Vec3 snap(Vec3 v) { return {snap(v.x), snap(v.y), snap(v.z)}; }
bool is_axis(Vec3 v) {
  int ones = 0;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(v[i]) == 1) ++ones;
    else if (v[i] != 0) return false;
  }
  return ones == 1;
}

// n + 1 values from a to b, in double, rounded once to f32.
std::vector<float> linspace(double a, double b, int n) {
  std::vector<float> v(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) v[static_cast<std::size_t>(i)] = static_cast<float>(a + (b - a) * i / n);
  return v;
}

}  // namespace

bool parse_view_direction(const std::string& name, ViewDirection& out) {
  for (const NamedView& v : kViews)
    if (name == v.name) {
      out = v.view;
      return true;
    }
  return false;
}

const char* view_direction_name(ViewDirection view) {
  for (const NamedView& v : kViews)
    if (v.view == view) return v.name;
  return "?";
}

void view_angles(ViewDirection view, double& yaw, double& pitch) {
  for (const NamedView& v : kViews)
    if (v.view == view) {
      yaw = v.yaw;
      pitch = v.pitch;
      return;
    }
  FREP_ASSERT(false, "unknown view direction");
}

void fit_pixels(double a, double b, int size, int& count_a, int& count_b) {
  const double longer = std::max(a, b);
  auto count = [&](double e) {
    if (!(longer > 0)) return size;
    return std::clamp(static_cast<int>(std::ceil(e / longer * size - 1e-9)), 1, size);
  };
  count_a = count(a);
  count_b = count(b);
}

Camera make_camera(const Box3& bounds, double yaw_degrees, double pitch_degrees, int size, int depth_steps,
                   bool z_up) {
  if (bounds.empty() || !(bounds.size().x > 0 && bounds.size().y > 0 && bounds.size().z > 0))
    throw InputError("", 0, "the render bounds must have positive extent along x, y and z");
  if (size < 1 || size > 16384) throw InputError("", 0, "image size must be between 1 and 16384, got " + std::to_string(size));
  if (depth_steps < 0 || depth_steps > 65536)
    throw InputError("", 0, "depth steps must be between 0 (automatic) and 65536, got " + std::to_string(depth_steps));
  const double yaw = yaw_degrees * std::numbers::pi / 180, pitch = pitch_degrees * std::numbers::pi / 180;
  Camera c;
  c.center = bounds.center();
  // In a y-up frame (front viewer at +z), then mapped to the model: with z up, the frame's
  // (X, Y, Z) are the model's (x, z, -y), still right-handed.
  auto model = [&](Vec3 v) { return snap(z_up ? Vec3{v.x, -v.z, v.y} : v); };
  const Vec3 toward{std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch)};
  const Vec3 right{std::cos(yaw), 0, -std::sin(yaw)};
  c.toward = model(toward);
  c.right = model(right);
  c.up = model(cross(toward, right));
  c.axis_aligned = is_axis(c.right) && is_axis(c.up) && is_axis(c.toward);
  // Half extents of the rotated box along each view axis.
  const Vec3 h = bounds.size() * 0.5;
  auto extent = [&](Vec3 axis) { return std::fabs(axis.x) * h.x + std::fabs(axis.y) * h.y + std::fabs(axis.z) * h.z; };
  const double eu = extent(c.right), ev = extent(c.up), ew = extent(c.toward);
  fit_pixels(eu, ev, size, c.width, c.height);
  const double pixel = 2 * std::max(eu, ev) / size;
  // Square pixels: the shorter side grows to a whole number of pixels (less than one more).
  c.half_u = eu >= ev ? eu : std::max(eu, c.width * pixel / 2);
  c.half_v = ev >= eu ? ev : std::max(ev, c.height * pixel / 2);
  c.half_w = ew;
  c.depth = depth_steps > 0 ? depth_steps : std::clamp(static_cast<int>(std::ceil(2 * ew / pixel - 1e-9)), 1, 65536);
  return c;
}

std::vector<float> Camera::u_edges() const { return linspace(-half_u, half_u, width); }
std::vector<float> Camera::v_edges() const { return linspace(half_v, -half_v, height); }
std::vector<float> Camera::w_samples() const { return linspace(half_w, -half_w, depth); }

std::vector<float> Camera::centers(const std::vector<float>& edges) {
  std::vector<float> c(edges.size() > 0 ? edges.size() - 1 : 0);
  // In double: the float sum of two edges near the float range's end overflows.
  for (std::size_t i = 0; i < c.size(); ++i) c[i] = static_cast<float>(0.5 * (static_cast<double>(edges[i]) + edges[i + 1]));
  return c;
}

}  // namespace frep
