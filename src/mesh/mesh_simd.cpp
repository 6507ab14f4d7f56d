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

#include <cmath>
#include <cstdint>

#include "frep/error.hpp"
#include "mesh/mesh_simd.hpp"

HWY_BEFORE_NAMESPACE();
namespace frep::mesh_detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Four lanes where the target has them (AVX2, AVX-512), else two vectors of two (SSE4).
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
    if (!(e.d2 < best)) continue;
    if (e.child < 0) {
      for (std::uint32_t k = 0; k < e.packets; ++k) {
        const TriPacket& t = packets[~e.child + k];
        for (std::size_t j = 0; j < kWidth; j += N) hn::Store(PacketDistance2(t, j, px, py, pz), d, dist + j);
        for (int j = 0; j < kWidth; ++j)
          if (dist[j] < best) best = dist[j], best_tri = t.tri[j];
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
      if (!(dist[j] < best)) continue;
      int k = m++;
      for (; k > 0 && dist[order[k - 1]] < dist[j]; --k) order[k] = order[k - 1];
      order[k] = j;
    }
    FREP_ASSERT(sp + m <= int(sizeof stack / sizeof stack[0]), "BVH deeper than the closest-point stack");
    for (int k = 0; k < m; ++k) stack[sp++] = {n.child[order[k]], n.packets[order[k]], dist[order[k]]};
  }
  return best_tri;
}

}  // namespace HWY_NAMESPACE
}  // namespace frep::mesh_detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace frep::mesh_detail {
HWY_EXPORT(NearestTriangle);

std::uint32_t nearest_triangle(const WideNode* nodes, const TriPacket* packets, const Vec3& p, double& d2) {
  return HWY_DYNAMIC_DISPATCH(NearestTriangle)(nodes, packets, p, d2);
}

}  // namespace frep::mesh_detail
#endif  // HWY_ONCE
