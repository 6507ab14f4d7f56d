#include "frep/mesh/bvh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "frep/error.hpp"

namespace frep {
namespace {

float down(double v) {
  float f = static_cast<float>(v);
  if (double(f) > v) f = std::nextafter(f, -INFINITY);
  return f;
}
float up(double v) {
  float f = static_cast<float>(v);
  if (double(f) < v) f = std::nextafter(f, INFINITY);
  return f;
}

struct Builder {
  const TriMesh& mesh;
  BvhOptions opt;
  std::vector<Vec3> lo, hi, centroid;  // per triangle (mesh order)
  std::vector<std::uint32_t>& order;
  std::vector<TriangleBvh::Node>& nodes;

  static double area(Vec3 l, Vec3 h) {
    const Vec3 d = h - l;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }

  void set_box(TriangleBvh::Node& n, std::uint32_t begin, std::uint32_t end) {
    Vec3 l{INFINITY, INFINITY, INFINITY}, h{-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t i = begin; i < end; ++i) {
      l = min(l, lo[order[i]]);
      h = max(h, hi[order[i]]);
    }
    for (int c = 0; c < 3; ++c) {
      n.lo[c] = down(l[c]);
      n.hi[c] = up(h[c]);
    }
  }

  // Builds node `ni` over order[begin, end); iterative over an explicit stack to bound depth.
  void build() {
    struct Task {
      std::uint32_t node, begin, end, depth;
    };
    std::vector<Task> stack{{0, 0, static_cast<std::uint32_t>(order.size()), 0}};
    nodes.push_back({});
    const int bins = std::max(2, opt.bins);
    std::vector<Vec3> blo(bins), bhi(bins);
    std::vector<std::uint32_t> bcount(bins);
    std::vector<double> right_area(bins);
    std::vector<std::uint32_t> right_count(bins);
    while (!stack.empty()) {
      const Task t = stack.back();
      stack.pop_back();
      TriangleBvh::Node& n = nodes[t.node];
      set_box(n, t.begin, t.end);
      const std::uint32_t count = t.end - t.begin;
      if (count <= std::uint32_t(std::max(1, opt.max_leaf_size))) {
        n.index = t.begin;
        n.count = count;
        continue;
      }
      // Centroid bounds choose the axis; SAH over bins chooses the plane.
      Vec3 cl{INFINITY, INFINITY, INFINITY}, ch{-INFINITY, -INFINITY, -INFINITY};
      for (std::uint32_t i = t.begin; i < t.end; ++i) {
        cl = min(cl, centroid[order[i]]);
        ch = max(ch, centroid[order[i]]);
      }
      int best_axis = -1, best_bin = -1;
      double best_cost = INFINITY;
      for (int axis = 0; axis < 3; ++axis) {
        const double extent = ch[axis] - cl[axis];
        if (!(extent > 0)) continue;
        const double scale = bins / extent;
        std::fill(bcount.begin(), bcount.end(), 0);
        for (int b = 0; b < bins; ++b) blo[b] = {INFINITY, INFINITY, INFINITY}, bhi[b] = -blo[b];
        for (std::uint32_t i = t.begin; i < t.end; ++i) {
          const std::uint32_t tri = order[i];
          int b = std::min(bins - 1, static_cast<int>((centroid[tri][axis] - cl[axis]) * scale));
          ++bcount[b];
          blo[b] = min(blo[b], lo[tri]);
          bhi[b] = max(bhi[b], hi[tri]);
        }
        Vec3 rl{INFINITY, INFINITY, INFINITY}, rh = -rl;
        std::uint32_t rc = 0;
        for (int b = bins - 1; b > 0; --b) {
          rl = min(rl, blo[b]), rh = max(rh, bhi[b]), rc += bcount[b];
          right_area[b] = rc ? area(rl, rh) : 0;
          right_count[b] = rc;
        }
        Vec3 ll{INFINITY, INFINITY, INFINITY}, lh = -ll;
        std::uint32_t lc = 0;
        for (int b = 1; b < bins; ++b) {
          ll = min(ll, blo[b - 1]), lh = max(lh, bhi[b - 1]), lc += bcount[b - 1];
          if (lc == 0 || right_count[b] == 0) continue;
          const double cost = lc * area(ll, lh) + right_count[b] * right_area[b];
          if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
        }
      }
      std::uint32_t mid;
      if (t.depth >= 40) {
        // Deep enough: object median on the widest centroid axis keeps the depth logarithmic
        // (queries use fixed-size stacks).
        const Vec3 ext = ch - cl;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        mid = t.begin + count / 2;
        std::nth_element(order.begin() + t.begin, order.begin() + mid, order.begin() + t.end,
                         [&](std::uint32_t x, std::uint32_t y) { return centroid[x][axis] < centroid[y][axis]; });
      } else if (best_axis < 0) {
        mid = t.begin + count / 2;  // all centroids coincide: split by index
      } else {
        const double scale = bins / (ch[best_axis] - cl[best_axis]);
        auto it = std::partition(order.begin() + t.begin, order.begin() + t.end, [&](std::uint32_t tri) {
          return std::min(bins - 1, static_cast<int>((centroid[tri][best_axis] - cl[best_axis]) * scale)) < best_bin;
        });
        mid = static_cast<std::uint32_t>(it - order.begin());
        if (mid == t.begin || mid == t.end) mid = t.begin + count / 2;
      }
      const auto left = static_cast<std::uint32_t>(nodes.size());
      nodes[t.node].index = left;
      nodes[t.node].count = 0;
      nodes.push_back({});
      nodes.push_back({});
      stack.push_back({left + 1, mid, t.end, t.depth + 1});
      stack.push_back({left, t.begin, mid, t.depth + 1});
    }
  }
};

}  // namespace

TriangleBvh::TriangleBvh(const TriMesh& mesh, const BvhOptions& options) {
  const std::size_t n = mesh.triangles.size();
  if (n == 0) return;
  FREP_ASSERT(n < 0x7fffffffu, "too many triangles for the BVH");
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  Builder b{mesh, options, {}, {}, {}, order_, nodes_};
  b.lo.resize(n), b.hi.resize(n), b.centroid.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 p0 = mesh.corner(t, 0), p1 = mesh.corner(t, 1), p2 = mesh.corner(t, 2);
    b.lo[t] = min(min(p0, p1), p2);
    b.hi[t] = max(max(p0, p1), p2);
    b.centroid[t] = (b.lo[t] + b.hi[t]) * 0.5;
  }
  nodes_.reserve(2 * n / std::max(1, options.max_leaf_size) + 8);
  b.build();
  tri_box_.resize(6 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t t = order_[i];
    for (int c = 0; c < 3; ++c) {
      tri_box_[6 * i + c] = down(b.lo[t][c]);
      tri_box_[6 * i + 3 + c] = up(b.hi[t][c]);
    }
  }
}

}  // namespace frep
