// SIMD kernels of the mesh-distance queries. Highway compiles this file once per instruction set
// and picks the best one for the CPU at run time. Everything is double precision: the closest
// point is the exact oracle other tests compare against.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)  // fewer copies, faster builds
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "mesh/mesh_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <cmath>
#include <cstdint>

#include "frep/error.hpp"
#include "mesh/mesh_simd.hpp"

HWY_BEFORE_NAMESPACE();
namespace frep::mesh_detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// kWidth lanes where the target has them (AVX-512), else several vectors (AVX2, SSE4).
using D = hn::CappedTag<double, kWidth>;
using V = hn::Vec<D>;

HWY_INLINE V Dot(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// Squared distance from p to the segment from corner (ux, uy, uz) = p - v along edge e.
HWY_INLINE V SegmentDistance2(V ux, V uy, V uz, V ex, V ey, V ez, V inv_e2) {
  const D d;
  const V t = hn::Min(hn::Max(hn::Mul(Dot(ux, uy, uz, ex, ey, ez), inv_e2), hn::Zero(d)), hn::Set(d, 1.0));
  const V wx = hn::Sub(ux, hn::Mul(ex, t)), wy = hn::Sub(uy, hn::Mul(ey, t)), wz = hn::Sub(uz, hn::Mul(ez, t));
  return Dot(wx, wy, wz, wx, wy, wz);
}

// Side of edge e (from corner u = p - v) within the triangle's plane: > 0 strictly inside.
HWY_INLINE V EdgeSide(V ux, V uy, V uz, V ex, V ey, V ez, V nx, V ny, V nz) {
  // (p - v) . (n x e): the sign of ((q - v) x e') . n for the projection q of p, branch-free.
  const V mx = hn::Sub(hn::Mul(ny, ez), hn::Mul(nz, ey));
  const V my = hn::Sub(hn::Mul(nz, ex), hn::Mul(nx, ez));
  const V mz = hn::Sub(hn::Mul(nx, ey), hn::Mul(ny, ex));
  return Dot(ux, uy, uz, mx, my, mz);
}

// Squared distances from p to the lanes [j, j + Lanes) of a packet: the plane distance when p
// projects strictly inside the triangle, else the nearest of the three edges. Branch-free, so
// degenerate triangles (n = 0: never "inside") need no special case.
HWY_INLINE V PacketDistance2(const TriPacket& t, std::size_t j, V px, V py, V pz) {
  const D d;
  const V ax = hn::Load(d, t.a[0] + j), ay = hn::Load(d, t.a[1] + j), az = hn::Load(d, t.a[2] + j);
  const V bx = hn::Load(d, t.b[0] + j), by = hn::Load(d, t.b[1] + j), bz = hn::Load(d, t.b[2] + j);
  const V cx = hn::Load(d, t.c[0] + j), cy = hn::Load(d, t.c[1] + j), cz = hn::Load(d, t.c[2] + j);
  const V uax = hn::Sub(px, ax), uay = hn::Sub(py, ay), uaz = hn::Sub(pz, az);
  const V ubx = hn::Sub(px, bx), uby = hn::Sub(py, by), ubz = hn::Sub(pz, bz);
  const V ucx = hn::Sub(px, cx), ucy = hn::Sub(py, cy), ucz = hn::Sub(pz, cz);
  const V e0x = hn::Sub(bx, ax), e0y = hn::Sub(by, ay), e0z = hn::Sub(bz, az);
  const V e1x = hn::Sub(cx, bx), e1y = hn::Sub(cy, by), e1z = hn::Sub(cz, bz);
  const V e2x = hn::Sub(ax, cx), e2y = hn::Sub(ay, cy), e2z = hn::Sub(az, cz);
  const V edge = hn::Min(hn::Min(SegmentDistance2(uax, uay, uaz, e0x, e0y, e0z, hn::Load(d, t.inv_e2[0] + j)),
                                 SegmentDistance2(ubx, uby, ubz, e1x, e1y, e1z, hn::Load(d, t.inv_e2[1] + j))),
                         SegmentDistance2(ucx, ucy, ucz, e2x, e2y, e2z, hn::Load(d, t.inv_e2[2] + j)));
  const V nx = hn::Load(d, t.n[0] + j), ny = hn::Load(d, t.n[1] + j), nz = hn::Load(d, t.n[2] + j);
  const V h = Dot(uax, uay, uaz, nx, ny, nz);
  const V face = hn::Mul(hn::Mul(h, h), hn::Load(d, t.inv_n2 + j));
  const V zero = hn::Zero(d);
  const auto inside = hn::And(hn::And(hn::Gt(EdgeSide(uax, uay, uaz, e0x, e0y, e0z, nx, ny, nz), zero),
                                      hn::Gt(EdgeSide(ubx, uby, ubz, e1x, e1y, e1z, nx, ny, nz), zero)),
                              hn::Gt(EdgeSide(ucx, ucy, ucz, e2x, e2y, e2z, nx, ny, nz), zero));
  return hn::IfThenElse(inside, face, edge);
}

std::uint32_t NearestTriangle(const WideNode* nodes, const TriPacket* packets, const Vec3& p, double& best) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V px = hn::Set(d, p.x), py = hn::Set(d, p.y), pz = hn::Set(d, p.z), zero = hn::Zero(d);
  HWY_ALIGN double dist[kWidth];
  std::uint32_t best_tri = UINT32_MAX;
  struct Entry {
    std::int32_t child;
    std::uint32_t packets;
    double d2;
  };
  // Depth-first, nearer boxes first; each node pushes at most kWidth entries and the wide tree
  // is no deeper than the binary one (at most ~72 levels, see bvh.cpp).
  Entry stack[kWidth * 80];
  int sp = 0;
  stack[sp++] = {0, 0, 0.0};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (!(e.d2 <= best)) continue;
    if (e.child < 0) {
      for (std::uint32_t k = 0; k < e.packets; ++k) {
        const TriPacket& t = packets[~e.child + k];
        for (std::size_t j = 0; j < kWidth; j += N) hn::Store(PacketDistance2(t, j, px, py, pz), d, dist + j);
        for (int j = 0; j < kWidth; ++j)
          if (dist[j] < best || (dist[j] == best && t.tri[j] < best_tri)) best = dist[j], best_tri = t.tri[j];
      }
      continue;
    }
    const WideNode& n = nodes[e.child];
    for (std::size_t j = 0; j < kWidth; j += N) {
      // Per axis max(lo - p, p - hi, 0): the gap to the box (infinite for an empty slot).
      const V dx = hn::Max(hn::Max(hn::Sub(hn::Load(d, n.lo[0] + j), px), hn::Sub(px, hn::Load(d, n.hi[0] + j))), zero);
      const V dy = hn::Max(hn::Max(hn::Sub(hn::Load(d, n.lo[1] + j), py), hn::Sub(py, hn::Load(d, n.hi[1] + j))), zero);
      const V dz = hn::Max(hn::Max(hn::Sub(hn::Load(d, n.lo[2] + j), pz), hn::Sub(pz, hn::Load(d, n.hi[2] + j))), zero);
      hn::Store(Dot(dx, dy, dz, dx, dy, dz), d, dist + j);
    }
    // Push the children within reach, farthest first so the nearest is visited next.
    int order[kWidth], m = 0;
    for (int j = 0; j < kWidth; ++j) {
      // Boxes as far as the best too: they may hold a tie with a smaller index. (Empty slots are
      // infinitely far, also when nothing is found yet.)
      if (!(dist[j] <= best) || dist[j] == INFINITY) continue;
      int k = m++;
      for (; k > 0 && dist[order[k - 1]] < dist[j]; --k) order[k] = order[k - 1];
      order[k] = j;
    }
    FREP_ASSERT(sp + m <= int(sizeof stack / sizeof stack[0]), "BVH deeper than the closest-point stack");
    for (int k = 0; k < m; ++k) stack[sp++] = {n.child[order[k]], n.packets[order[k]], dist[order[k]]};
  }
  return best_tri;
}

// The nearest triangle a ray o + t d meets with t in [0, t_max] (Moller-Trumbore, double, the
// barycentric tests widened by 1e-12 so that a ray through an edge meets one of its triangles at
// least); ties go to the smallest index. `t_max` receives the hit's t.
std::uint32_t FirstHit(const WideNode* nodes, const TriPacket* packets, const Vec3& o, const Vec3& dir, double& t_max) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  // Zero direction components become tiny ones (no 0 * inf = NaN in the slab tests).
  Vec3 dv = dir;
  for (int a = 0; a < 3; ++a)
    if (dv[a] == 0) dv[a] = 1e-300;
  const V ox = hn::Set(d, o.x), oy = hn::Set(d, o.y), oz = hn::Set(d, o.z);
  const V dx = hn::Set(d, dv.x), dy = hn::Set(d, dv.y), dz = hn::Set(d, dv.z);
  const V ix = hn::Set(d, 1 / dv.x), iy = hn::Set(d, 1 / dv.y), iz = hn::Set(d, 1 / dv.z);
  const V zero = hn::Zero(d), eps = hn::Set(d, -1e-12), one_eps = hn::Set(d, 1 + 1e-12);
  HWY_ALIGN double tn[kWidth], th[kWidth];
  double best = t_max;
  std::uint32_t best_tri = UINT32_MAX;
  struct Entry {
    std::int32_t child;
    std::uint32_t packets;
    double t;
  };
  Entry stack[kWidth * 80];
  int sp = 0;
  stack[sp++] = {0, 0, 0.0};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (!(e.t <= best)) continue;
    if (e.child < 0) {
      for (std::uint32_t k = 0; k < e.packets; ++k) {
        const TriPacket& t = packets[~e.child + k];
        for (std::size_t j = 0; j < kWidth; j += N) {
          const V ax = hn::Load(d, t.a[0] + j), ay = hn::Load(d, t.a[1] + j), az = hn::Load(d, t.a[2] + j);
          const V e1x = hn::Sub(hn::Load(d, t.b[0] + j), ax), e1y = hn::Sub(hn::Load(d, t.b[1] + j), ay),
                  e1z = hn::Sub(hn::Load(d, t.b[2] + j), az);
          const V e2x = hn::Sub(hn::Load(d, t.c[0] + j), ax), e2y = hn::Sub(hn::Load(d, t.c[1] + j), ay),
                  e2z = hn::Sub(hn::Load(d, t.c[2] + j), az);
          // p = d x e2, det = e1 . p
          const V px = hn::Sub(hn::Mul(dy, e2z), hn::Mul(dz, e2y)), py = hn::Sub(hn::Mul(dz, e2x), hn::Mul(dx, e2z)),
                  pz = hn::Sub(hn::Mul(dx, e2y), hn::Mul(dy, e2x));
          const V det = Dot(e1x, e1y, e1z, px, py, pz);
          const V inv = hn::Div(hn::Set(d, 1.0), det);
          const V sx = hn::Sub(ox, ax), sy = hn::Sub(oy, ay), sz = hn::Sub(oz, az);
          const V u = hn::Mul(Dot(sx, sy, sz, px, py, pz), inv);
          // q = s x e1
          const V qx = hn::Sub(hn::Mul(sy, e1z), hn::Mul(sz, e1y)), qy = hn::Sub(hn::Mul(sz, e1x), hn::Mul(sx, e1z)),
                  qz = hn::Sub(hn::Mul(sx, e1y), hn::Mul(sy, e1x));
          const V v = hn::Mul(Dot(dx, dy, dz, qx, qy, qz), inv);
          const V tt = hn::Mul(Dot(e2x, e2y, e2z, qx, qy, qz), inv);
          // Degenerate triangles and rays in their plane give det = 0: inv infinite, u or v NaN or
          // infinite, and the tests below fail.
          const auto ok = hn::And(hn::And(hn::Ge(u, eps), hn::Ge(v, eps)),
                                  hn::And(hn::Le(hn::Add(u, v), one_eps), hn::Ge(tt, zero)));
          hn::Store(hn::IfThenElse(ok, tt, hn::Set(d, INFINITY)), d, tn + j);
        }
        for (int j = 0; j < kWidth; ++j)
          if (tn[j] != INFINITY && (tn[j] < best || (tn[j] == best && t.tri[j] < best_tri))) best = tn[j], best_tri = t.tri[j];
      }
      continue;
    }
    const WideNode& n = nodes[e.child];
    for (std::size_t j = 0; j < kWidth; j += N) {
      const V t0x = hn::Mul(hn::Sub(hn::Load(d, n.lo[0] + j), ox), ix), t1x = hn::Mul(hn::Sub(hn::Load(d, n.hi[0] + j), ox), ix);
      const V t0y = hn::Mul(hn::Sub(hn::Load(d, n.lo[1] + j), oy), iy), t1y = hn::Mul(hn::Sub(hn::Load(d, n.hi[1] + j), oy), iy);
      const V t0z = hn::Mul(hn::Sub(hn::Load(d, n.lo[2] + j), oz), iz), t1z = hn::Mul(hn::Sub(hn::Load(d, n.hi[2] + j), oz), iz);
      const V near = hn::Max(hn::Max(hn::Min(t0x, t1x), hn::Min(t0y, t1y)), hn::Max(hn::Min(t0z, t1z), zero));
      const V far = hn::Min(hn::Min(hn::Max(t0x, t1x), hn::Max(t0y, t1y)), hn::Max(t0z, t1z));
      hn::Store(near, d, tn + j);
      hn::Store(far, d, th + j);
    }
    // Children the ray crosses before the best hit, nearest visited first.
    int order[kWidth], m = 0;
    for (int j = 0; j < kWidth; ++j) {
      if (n.child[j] == 0 && n.packets[j] == 0) continue;  // an empty slot
      // Boxes are grown a little: the slab test rounds, and a ray along a face must not miss.
      const double slack = 1e-12 * (std::fabs(tn[j]) + std::fabs(th[j]));
      if (!(tn[j] <= th[j] + slack) || !(tn[j] <= best)) continue;
      int k = m++;
      for (; k > 0 && tn[order[k - 1]] < tn[j]; --k) order[k] = order[k - 1];
      order[k] = j;
    }
    FREP_ASSERT(sp + m <= int(sizeof stack / sizeof stack[0]), "BVH deeper than the ray stack");
    for (int k = 0; k < m; ++k) stack[sp++] = {n.child[order[k]], n.packets[order[k]], tn[order[k]]};
  }
  t_max = best;
  return best_tri;
}

// atan2 with the std::atan2 conventions on zeros (signed results, atan2(0, 0) = 0), built on
// Highway's atan of the octant ratio min/max in [0, 1].
HWY_INLINE V Atan2(V y, V x) {
  const D d;
  const V ax = hn::Abs(x), ay = hn::Abs(y), zero = hn::Zero(d);
  const V hi = hn::Max(ax, ay);
  V r = hn::Atan(d, hn::IfThenElseZero(hn::Gt(hi, zero), hn::Div(hn::Min(ax, ay), hi)));
  r = hn::IfThenElse(hn::Gt(ay, ax), hn::Sub(hn::Set(d, 1.5707963267948966), r), r);
  // x < 0, or x = -0 (std::atan2(+-0, -0) = +-pi).
  r = hn::IfThenElse(hn::Lt(hn::CopySign(hn::Set(d, 1.0), x), zero), hn::Sub(hn::Set(d, 3.141592653589793), r), r);
  return hn::CopySign(r, y);
}

// Signed solid angles of the lanes [j, j + Lanes) of a packet seen from p (Van Oosterom and
// Strackee, as in mesh_distance.cpp), zero for padding lanes.
HWY_INLINE V PacketSolidAngle(const TriPacket& t, std::size_t j, V px, V py, V pz) {
  const D d;
  const V ax = hn::Sub(hn::Load(d, t.a[0] + j), px), ay = hn::Sub(hn::Load(d, t.a[1] + j), py),
          az = hn::Sub(hn::Load(d, t.a[2] + j), pz);
  const V bx = hn::Sub(hn::Load(d, t.b[0] + j), px), by = hn::Sub(hn::Load(d, t.b[1] + j), py),
          bz = hn::Sub(hn::Load(d, t.b[2] + j), pz);
  const V cx = hn::Sub(hn::Load(d, t.c[0] + j), px), cy = hn::Sub(hn::Load(d, t.c[1] + j), py),
          cz = hn::Sub(hn::Load(d, t.c[2] + j), pz);
  const V la = hn::Sqrt(Dot(ax, ay, az, ax, ay, az)), lb = hn::Sqrt(Dot(bx, by, bz, bx, by, bz)),
          lc = hn::Sqrt(Dot(cx, cy, cz, cx, cy, cz));
  const V num = Dot(ax, ay, az, hn::Sub(hn::Mul(by, cz), hn::Mul(bz, cy)), hn::Sub(hn::Mul(bz, cx), hn::Mul(bx, cz)),
                    hn::Sub(hn::Mul(bx, cy), hn::Mul(by, cx)));
  const V den = hn::Add(hn::Add(hn::Add(hn::Mul(hn::Mul(la, lb), lc), hn::Mul(Dot(ax, ay, az, bx, by, bz), lc)),
                                hn::Mul(Dot(bx, by, bz, cx, cy, cz), la)),
                        hn::Mul(Dot(cx, cy, cz, ax, ay, az), lb));
  return hn::Mul(hn::Mul(hn::Set(d, 2.0), Atan2(num, den)), hn::Load(d, t.real + j));
}

double SolidAngleSum(const WideNode* nodes, const WideDipoles* dipoles, const TriPacket* packets, const Vec3& p) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V px = hn::Set(d, p.x), py = hn::Set(d, p.y), pz = hn::Set(d, p.z);
  V sum = hn::Zero(d);
  HWY_ALIGN double is_far[kWidth];
  std::uint32_t stack[kWidth * 80];  // see NearestTriangle
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const std::uint32_t ni = stack[--sp];
    const WideNode& n = nodes[ni];
    const WideDipoles& w = dipoles[ni];
    for (std::size_t j = 0; j < kWidth; j += N) {
      const V dx = hn::Sub(hn::Load(d, w.center[0] + j), px), dy = hn::Sub(hn::Load(d, w.center[1] + j), py),
              dz = hn::Sub(hn::Load(d, w.center[2] + j), pz);
      const V dist2 = Dot(dx, dy, dz, dx, dy, dz);
      const auto far = hn::Gt(dist2, hn::Load(d, w.far2 + j));  // never for an empty slot (far2 = inf)
      const V dip = hn::Div(Dot(dx, dy, dz, hn::Load(d, w.area_normal[0] + j), hn::Load(d, w.area_normal[1] + j),
                                hn::Load(d, w.area_normal[2] + j)),
                            hn::Mul(dist2, hn::Sqrt(dist2)));
      sum = hn::Add(sum, hn::IfThenElseZero(far, dip));
      hn::Store(hn::VecFromMask(d, far), d, is_far + j);
    }
    for (int j = 0; j < kWidth; ++j) {
      if (is_far[j] != 0 || (n.child[j] == 0 && n.packets[j] == 0)) continue;  // dipole, or empty slot
      if (n.child[j] >= 0) {
        FREP_ASSERT(sp < int(sizeof stack / sizeof stack[0]), "BVH deeper than the winding-number stack");
        stack[sp++] = static_cast<std::uint32_t>(n.child[j]);
        continue;
      }
      for (std::uint32_t k = 0; k < n.packets[j]; ++k)
        for (std::size_t l = 0; l < kWidth; l += N)
          sum = hn::Add(sum, PacketSolidAngle(packets[~n.child[j] + k], l, px, py, pz));
    }
  }
  return hn::GetLane(hn::SumOfLanes(d, sum));
}

}  // namespace HWY_NAMESPACE
}  // namespace frep::mesh_detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep::mesh_detail {
HWY_EXPORT(NearestTriangle);
HWY_EXPORT(SolidAngleSum);
HWY_EXPORT(FirstHit);

std::uint32_t first_hit(const WideNode* nodes, const TriPacket* packets, const Vec3& o, const Vec3& dir, double& t_max) {
  return HWY_DYNAMIC_DISPATCH(FirstHit)(nodes, packets, o, dir, t_max);
}

std::uint32_t nearest_triangle(const WideNode* nodes, const TriPacket* packets, const Vec3& p, double& d2) {
  return HWY_DYNAMIC_DISPATCH(NearestTriangle)(nodes, packets, p, d2);
}

double solid_angle_sum(const WideNode* nodes, const WideDipoles* dipoles, const TriPacket* packets, const Vec3& p) {
  return HWY_DYNAMIC_DISPATCH(SolidAngleSum)(nodes, dipoles, packets, p);
}

}  // namespace frep::mesh_detail
#endif  // HWY_ONCE
