#include "tri_tri.hpp"

#include <utility>

#include "predicates.hpp"

namespace frep {
namespace {

using exact::orient2d;
using exact::orient3d;

// Picks the corner that is alone on its side of the other triangle's plane (Guigue-Devillers):
// returns its index and whether the other triangle must be flipped so that the lone corner
// counts as positive and the other two as non-positive.
bool lone_corner(const int s[3], int& r, bool& flip) {
  for (int i = 0; i < 3; ++i) {
    const int a = s[i], b = s[(i + 1) % 3], c = s[(i + 2) % 3];
    if (a > 0 && b <= 0 && c <= 0) { r = i; flip = false; return true; }
    if (a < 0 && b >= 0 && c >= 0) { r = i; flip = true; return true; }
    if (a == 0 && b > 0 && c > 0) { r = i; flip = true; return true; }
    if (a == 0 && b < 0 && c < 0) { r = i; flip = false; return true; }
  }
  return false;
}

// Projects onto the coordinate plane in which triangle p is not degenerate.
struct Projection {
  int u = 0, v = 1;
  explicit Projection(const Vec3 p[3]) {
    const int choices[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    for (const auto& c : choices)
      if (orient2d(p[0][c[0]], p[0][c[1]], p[1][c[0]], p[1][c[1]], p[2][c[0]], p[2][c[1]]) != 0) {
        u = c[0], v = c[1];
        return;
      }
  }
  int orient(const Vec3& a, const Vec3& b, const Vec3& c) const { return orient2d(a[u], a[v], b[u], b[v], c[u], c[v]); }
};

// Coplanar triangles: Overlap if the interiors share area, Touch if only boundaries meet, None
// if disjoint. Separating-axis test over the six edge lines, exact.
Contact coplanar_contact(const Vec3 p[3], const Vec3 q[3]) {
  const Projection pr(p);
  bool weakly_separated = false;
  for (int pass = 0; pass < 2; ++pass) {
    const Vec3* a = pass == 0 ? p : q;
    const Vec3* b = pass == 0 ? q : p;
    for (int e = 0; e < 3; ++e) {
      const Vec3 &e0 = a[e], &e1 = a[(e + 1) % 3], &inner = a[(e + 2) % 3];
      const int in = pr.orient(e0, e1, inner);
      int strictly_out = 0, out_or_on = 0;
      for (int k = 0; k < 3; ++k) {
        const int s = pr.orient(e0, e1, b[k]) * in;
        strictly_out += s < 0;
        out_or_on += s <= 0;
      }
      if (strictly_out == 3) return Contact::None;
      if (out_or_on == 3) weakly_separated = true;
    }
  }
  return weakly_separated ? Contact::Touch : Contact::Overlap;
}

// Non-coplanar triangles with signs dp (p's corners against q's plane) and dq: does the
// intersection of the closed triangles (strict = false) or of their interiors (strict = true)
// exist? Guigue and Devillers' interval test on the line where the planes meet.
bool planes_overlap(const Vec3 p_in[3], const Vec3 q_in[3], const int dp[3], bool strict) {
  int r;
  bool flip;
  if (!lone_corner(dp, r, flip)) return false;
  Vec3 p[3] = {p_in[r], p_in[(r + 1) % 3], p_in[(r + 2) % 3]};
  Vec3 q[3] = {q_in[0], q_in[1], q_in[2]};
  if (flip) std::swap(q[1], q[2]);
  int dq[3];
  for (int i = 0; i < 3; ++i) dq[i] = orient3d(p[0], p[1], p[2], q[i]);
  if (!lone_corner(dq, r, flip)) return false;
  const Vec3 qq[3] = {q[r], q[(r + 1) % 3], q[(r + 2) % 3]};
  if (flip) std::swap(p[1], p[2]);
  const int a = orient3d(p[0], p[1], qq[0], qq[1]);
  const int b = orient3d(p[0], p[2], qq[0], qq[2]);
  return strict ? (a < 0 && b > 0) : (a <= 0 && b >= 0);
}

bool straddles(const int s[3]) {
  const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0;
  const bool neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
  return pos && neg;
}

}  // namespace

Contact classify_triangle_pair(const Vec3 p[3], const unsigned pi[3], const Vec3 q[3], const unsigned qi[3]) {
  int shared = 0, ps[3] = {-1, -1, -1};  // ps[i]: index in q of p's corner i, or -1
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (pi[i] == qi[j]) ps[i] = j, ++shared;
  if (shared >= 3) return Contact::None;  // same corners: a duplicate, reported separately
  if (shared == 2) {
    // Neighbours across an edge meet beyond it only when folded flat onto each other.
    int c = 0;
    while (ps[c] >= 0) ++c;  // p's corner off the shared edge
    int d = 0;
    while (d == ps[0] || d == ps[1] || d == ps[2]) ++d;  // q's corner off the shared edge
    const Vec3 &a = p[(c + 1) % 3], &b = p[(c + 2) % 3];
    if (orient3d(a, b, p[c], q[d]) != 0) return Contact::None;
    const Projection pr(p);
    return pr.orient(a, b, p[c]) == pr.orient(a, b, q[d]) ? Contact::Overlap : Contact::None;
  }
  int dp[3], dq[3];
  for (int i = 0; i < 3; ++i) dp[i] = orient3d(q[0], q[1], q[2], p[i]);
  if ((dp[0] > 0 && dp[1] > 0 && dp[2] > 0) || (dp[0] < 0 && dp[1] < 0 && dp[2] < 0)) return Contact::None;
  if (dp[0] == 0 && dp[1] == 0 && dp[2] == 0) {
    const Contact c = coplanar_contact(p, q);
    return (shared > 0 && c == Contact::Touch) ? Contact::None : c;
  }
  for (int i = 0; i < 3; ++i) dq[i] = orient3d(p[0], p[1], p[2], q[i]);
  if ((dq[0] > 0 && dq[1] > 0 && dq[2] > 0) || (dq[0] < 0 && dq[1] < 0 && dq[2] < 0)) return Contact::None;
  if (straddles(dp) && straddles(dq) && planes_overlap(p, q, dp, true)) return Contact::Cross;
  if (shared > 0) return Contact::None;  // neighbours at a vertex: touching there is expected
  return planes_overlap(p, q, dp, false) ? Contact::Touch : Contact::None;
}

}  // namespace frep
