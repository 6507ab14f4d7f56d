// Affine maps of space, p -> M p + t, in double precision: how a field is moved, rotated and
// scaled (remapping its x, y, z), and how a camera's view coordinates map to the model's.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "frep/math/vec.hpp"

namespace frep {

struct Affine3 {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  // rows: m[i][0..2] . p + m[i][3]

  static Affine3 identity() { return {}; }
  static Affine3 translation(const Vec3& t) {
    Affine3 a;
    for (int i = 0; i < 3; ++i) a.m[i][3] = t[i];
    return a;
  }

  Vec3 apply(const Vec3& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  // The linear part's transpose times v: how a gradient found at apply(p) maps back to p.
  Vec3 apply_transposed(const Vec3& v) const {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
  }
  // (this * o)(p) = this(o(p)).
  Affine3 operator*(const Affine3& o) const {
    Affine3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = j == 3 ? m[i][3] : 0.0;
        for (int k = 0; k < 3; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  bool operator==(const Affine3& o) const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j)
        if (m[i][j] != o.m[i][j]) return false;
    return true;
  }
  bool is_identity() const { return *this == Affine3{}; }
  bool finite() const {
    for (const auto& row : m)
      for (double v : row)
        if (!std::isfinite(v)) return false;
    return true;
  }
  // The inverse map (adjugate over determinant), or nullopt when the linear part is singular or
  // the result is not finite. A translation inverts exactly (its linear part stays 1s and 0s).
  std::optional<Affine3> inverse() const {
    const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if (!(det != 0) || !std::isfinite(det)) return std::nullopt;
    const double r[3][3] = {{c00, m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][1] * m[1][2] - m[0][2] * m[1][1]},
                            {c01, m[0][0] * m[2][2] - m[0][2] * m[2][0], m[0][2] * m[1][0] - m[0][0] * m[1][2]},
                            {c02, m[0][1] * m[2][0] - m[0][0] * m[2][1], m[0][0] * m[1][1] - m[0][1] * m[1][0]}};
    Affine3 inv;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) inv.m[i][j] = r[i][j] / det;
      inv.m[i][3] = -(inv.m[i][0] * m[0][3] + inv.m[i][1] * m[1][3] + inv.m[i][2] * m[2][3]);
    }
    if (!inv.finite()) return std::nullopt;
    return inv;
  }
  // An upper bound of the linear part's largest stretch |M v| / |v| (its spectral norm): the
  // smaller of the Frobenius norm and the square root of the largest row sum of |M^T M|
  // (Gershgorin), which is exact, up to rounding, for rotations times a uniform scale.
  double stretch_bound() const {
    double g[3][3], frob = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        g[i][j] = m[0][i] * m[0][j] + m[1][i] * m[1][j] + m[2][i] * m[2][j];
        if (i == j) frob += g[i][i];
      }
    double row = 0;
    for (const auto& r : g) row = std::max(row, std::fabs(r[0]) + std::fabs(r[1]) + std::fabs(r[2]));
    // Rounding of the products above is far below this margin.
    return std::sqrt(std::min(frob, row)) * (1 + 1e-12);
  }
};

}  // namespace frep
