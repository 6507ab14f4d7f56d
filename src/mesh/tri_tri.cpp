// Triangle pair classification (tri_tri.hpp): signs of each triangle's corners against the
// other's plane, then Guigue and Devillers' interval test for non-coplanar pairs and a
// separating-axis test (or, for neighbours at a vertex, a test of the angles at that vertex)
// for coplanar ones. Every decision is an exact orientation sign. What makes it fast on meshes
// of flat faces, where most neighbours are coplanar and the predicates' float filter cannot
// certify a zero: signs known without computing them are not computed (a corner shared with the
// other triangle, and whatever the caller knows: PlaneHint), and the cheap parts are shared
// (one float filter per plane for its three corner tests, one projection per coplanar pair).
#include "frep/mesh/tri_tri.hpp"

#include <cmath>
#include <utility>

#include "frep/math/predicates.hpp"

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

// Projects onto a coordinate plane in which triangle p is not degenerate: the first of xy, yz,
// zx, or xy if there is none (every orientation in p's plane is then 0 anyway). `sp` is p's
// orientation there (the same for each rotation of its corners).
struct Projection {
  int u = 0, v = 1;
  int sp = 0;
  Projection() = default;
  explicit Projection(const Vec3 p[3]) {
    const int choices[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    for (const auto& c : choices)
      if ((sp = orient(p[0], p[1], p[2], c[0], c[1])) != 0) {
        u = c[0], v = c[1];
        return;
      }
  }
  // Any plane in which p is not degenerate, found faster: the one across p's largest normal
  // component, decided by the predicates' float filter nearly always (the first of xy, yz, zx
  // is often degenerate on CAD parts, whose faces are often axis-aligned), else as above. Which
  // plane does not matter to a test on p and another triangle in p's plane, as long as neither
  // is degenerate: each such projection is an affine bijection of that plane, which scales all
  // orientation signs by one common factor +-1, and the tests compare signs with each other.
  static Projection any(const Vec3 p[3]) {
    const int across[3][2] = {{1, 2}, {2, 0}, {0, 1}};  // x, y, z
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    const int k = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    Projection pr;
    if ((pr.sp = orient(p[0], p[1], p[2], across[k][0], across[k][1])) != 0) {
      pr.u = across[k][0], pr.v = across[k][1];
      return pr;
    }
    return Projection(p);
  }
  static int orient(const Vec3& a, const Vec3& b, const Vec3& c, int u, int v) {
    return orient2d(a[u], a[v], b[u], b[v], c[u], c[v]);
  }
  int orient(const Vec3& a, const Vec3& b, const Vec3& c) const { return orient(a, b, c, u, v); }
};

// Coplanar triangles: Overlap if the interiors share area, Touch if only boundaries meet, None
// if disjoint. Separating-axis test over the six edge lines, exact. A triangle's inner side is
// the same for its three edges (its orientation; cyclic order does not change it).
Contact coplanar_contact(const Vec3 p[3], const Vec3 q[3], const Projection& pr) {
  bool weakly_separated = false;
  for (int pass = 0; pass < 2; ++pass) {
    const Vec3* a = pass == 0 ? p : q;
    const Vec3* b = pass == 0 ? q : p;
    const int in = pass == 0 ? pr.sp : pr.orient(a[0], a[1], a[2]);
    for (int e = 0; e < 3; ++e) {
      const Vec3 &e0 = a[e], &e1 = a[(e + 1) % 3];
      int strictly_out = 0, out_or_on = 0;
      for (int k = 0; k < 3; ++k) {
        const int s = pr.orient(e0, e1, b[k]) * in;
        if (s > 0) break;  // a corner inside: this line separates nothing
        strictly_out += s < 0;
        ++out_or_on;
      }
      if (strictly_out == 3) return Contact::None;
      if (out_or_on == 3) weakly_separated = true;
    }
  }
  return weakly_separated ? Contact::Touch : Contact::Overlap;
}

// Coplanar triangles sharing exactly one corner v (p[i] = q[j]): Overlap or None (touching at a
// shared corner is expected). Near v each triangle is the wedge between its two edges at v, so
// the interiors overlap exactly when the open wedges do (each spans less than a half turn); two
// such wedges, both turning counter-clockwise from their first edge, overlap if and only if one
// starts inside the other, or both start along the same ray. What the separating-axis test
// answers, for at most six orientations instead of about thirty.
Contact coplanar_at_vertex(const Vec3 p[3], int i, const Vec3 q[3], int j, const Projection& pr) {
  const Vec3& v = p[i];
  const Vec3 *a1 = &p[(i + 1) % 3], *a2 = &p[(i + 2) % 3];
  const Vec3 *b1 = &q[(j + 1) % 3], *b2 = &q[(j + 2) % 3];
  const int op = pr.sp, oq = pr.orient(v, *b1, *b2);
  // A degenerate triangle has no interior (the separating-axis test finds its own edge lines
  // weakly separating: Touch, which a shared corner makes None).
  if (op == 0 || oq == 0) return Contact::None;
  if (op < 0) std::swap(a1, a2);
  if (oq < 0) std::swap(b1, b2);
  // b1 in [a1, a2): on a1's side of turning (or along a1, not opposite it) and before a2.
  if (pr.orient(v, *a1, *b1) >= 0 && pr.orient(v, *b1, *a2) > 0) return Contact::Overlap;
  // a1 strictly inside (b1, b2).
  if (pr.orient(v, *b1, *a1) > 0 && pr.orient(v, *a1, *b2) > 0) return Contact::Overlap;
  return Contact::None;
}

// Non-coplanar triangles with signs dp (p's corners against q's plane) and dq (q's against
// p's): does the intersection of the closed triangles (strict = false) or of their interiors
// (strict = true) exist? Guigue and Devillers' interval test on the line where the planes meet.
bool planes_overlap(const Vec3 p_in[3], const Vec3 q_in[3], const int dp[3], const int dq_in[3], bool strict) {
  int r;
  bool flip;
  if (!lone_corner(dp, r, flip)) return false;
  Vec3 p[3] = {p_in[r], p_in[(r + 1) % 3], p_in[(r + 2) % 3]};
  Vec3 q[3] = {q_in[0], q_in[1], q_in[2]};
  // q's signs against p's plane: p rotated keeps its orientation; q's corners follow the flip.
  int dq[3] = {dq_in[0], dq_in[1], dq_in[2]};
  if (flip) std::swap(q[1], q[2]), std::swap(dq[1], dq[2]);
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

// A float filter for orient3d(t[0], t[1], t[2], x) over many x: the sign of det[U, V, W] with
// rows U = t[1] - t[0], V = t[2] - t[0], W = x - t[0], evaluated in the shape of Shewchuk's
// orient3d (rounded differences of the inputs, each 2x2 minor times the third row's z, summed in
// order), for which his bound o3derrboundA holds whichever row is the one that varies. Products of
// U and V alone are computed once per triangle instead of once per corner tested.
struct PlaneFilter {
  Vec3 a;
  double ux, uy, uz, vx, vy, vz;
  double m, pm;  // U and V's xy minor, and the sum of its products' magnitudes
  explicit PlaneFilter(const Vec3 t[3]) : a(t[0]) {
    ux = t[1].x - a.x, uy = t[1].y - a.y, uz = t[1].z - a.z;
    vx = t[2].x - a.x, vy = t[2].y - a.y, vz = t[2].z - a.z;
    const double uxvy = ux * vy, vxuy = vx * uy;
    m = uxvy - vxuy;
    pm = std::fabs(uxvy) + std::fabs(vxuy);
  }
  // The sign where the filter decides it, else exact::kUndecided.
  int sign(const Vec3& x) const {
    const double wx = x.x - a.x, wy = x.y - a.y, wz = x.z - a.z;
    const double vxwy = vx * wy, wxvy = wx * vy;
    const double wxuy = wx * uy, uxwy = ux * wy;
    const double det = uz * (vxwy - wxvy) + vz * (wxuy - uxwy) + wz * m;
    const double permanent = (std::fabs(vxwy) + std::fabs(wxvy)) * std::fabs(uz) +
                             (std::fabs(wxuy) + std::fabs(uxwy)) * std::fabs(vz) + pm * std::fabs(wz);
    const double bound = 7.8e-16 * permanent;
    if (permanent > 1e-280) {
      if (det > bound) return 1;
      if (-det > bound) return -1;
    }
    return exact::kUndecided;
  }
};

// orient3d(t[0], t[1], t[2], x), where x is corner k of triangle `which`, where the shared
// filter could not decide: exactly as orient3d decides it (its own filter, its exact stage),
// except that a zero the caller knows is taken from it. Out of line: rare on most meshes.
[[gnu::noinline]] int side_undecided(const Vec3 t[3], const Vec3& x, int which, int k, const PlaneHint* hint) {
  double permanent;
  const int s = exact::orient3d_filter(t[0], t[1], t[2], x, permanent);
  if (s != exact::kUndecided) return s;
  if (permanent != 0 && hint && hint->on_plane(hint->context, which, k)) return 0;
  return exact::orient3d_uncertain(t[0], t[1], t[2], x, permanent);
}

// orient3d(t[0], t[1], t[2], x) through f, the filter of t's plane (the same answer).
[[gnu::always_inline]] inline int side(const PlaneFilter& f, const Vec3 t[3], const Vec3& x, int which, int k,
                                       const PlaneHint* hint) {
  const int s = f.sign(x);
  return s != exact::kUndecided ? s : side_undecided(t, x, which, k, hint);
}

bool all_one_side(const int s[3]) {
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

}  // namespace

Contact classify_triangle_pair(const Vec3 p[3], const unsigned pi[3], const Vec3 q[3], const unsigned qi[3],
                               bool coplanar, const PlaneHint* hint) {
  int shared = 0, ps[3] = {-1, -1, -1}, qs[3] = {-1, -1, -1};  // ps[i]: index in q of p's corner i, or -1
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (pi[i] == qi[j]) ps[i] = j, qs[j] = i, ++shared;
  if (shared >= 3) return Contact::None;  // same corners: a duplicate, reported separately
  if (shared == 2) {
    // Neighbours across an edge meet beyond it only when folded flat onto each other.
    int c = 0;
    while (ps[c] >= 0) ++c;  // p's corner off the shared edge
    int d = 0;
    while (d == ps[0] || d == ps[1] || d == ps[2]) ++d;  // q's corner off the shared edge
    const Vec3 &a = p[(c + 1) % 3], &b = p[(c + 2) % 3];
    if (!coplanar && orient3d(a, b, p[c], q[d]) != 0) return Contact::None;
    // (q is (a, b, q[d]): degenerate exactly where q[d] is on the line ab, in any projection.)
    const Projection pr = Projection::any(p);
    return pr.orient(a, b, p[c]) == pr.orient(a, b, q[d]) ? Contact::Overlap : Contact::None;
  }
  // A corner at the same point as a corner of the other triangle lies in its plane: sign 0.
  // (Shared indices mean the same point; the coordinates are compared too, so that a caller
  // breaking that rule gets the signs computed.)
  int dp[3] = {0, 0, 0}, dq[3];
  if (!coplanar) {
    const PlaneFilter fq(q);
    for (int i = 0; i < 3; ++i) dp[i] = ps[i] >= 0 && p[i] == q[ps[i]] ? 0 : side(fq, q, p[i], 0, i, hint);
  }
  if (all_one_side(dp)) return Contact::None;
  if (dp[0] == 0 && dp[1] == 0 && dp[2] == 0) {
    Projection pr = Projection::any(p);
    if (shared == 1) {
      int i = 0;
      while (ps[i] < 0) ++i;
      if (p[i] == q[ps[i]]) return coplanar_at_vertex(p, i, q, ps[i], pr);
    }
    // A degenerate q (all dp are 0 against its line, which need not lie in p's plane) is
    // projected as it always was.
    if (pr.orient(q[0], q[1], q[2]) == 0) pr = Projection(p);
    const Contact c = coplanar_contact(p, q, pr);
    return (shared > 0 && c == Contact::Touch) ? Contact::None : c;
  }
  const PlaneFilter fp(p);
  for (int j = 0; j < 3; ++j) dq[j] = qs[j] >= 0 && q[j] == p[qs[j]] ? 0 : side(fp, p, q[j], 1, j, hint);
  if (all_one_side(dq)) return Contact::None;
  if (straddles(dp) && straddles(dq) && planes_overlap(p, q, dp, dq, true)) return Contact::Cross;
  if (shared > 0) return Contact::None;  // neighbours at a vertex: touching there is expected
  return planes_overlap(p, q, dp, dq, false) ? Contact::Touch : Contact::None;
}

}  // namespace frep
