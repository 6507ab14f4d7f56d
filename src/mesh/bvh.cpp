// TriangleBvh (bvh.hpp): binned SAH over the triangles' box centres, built top-down over an explicit
// stack. Each node costs one pass over its triangles, which bins them on all three axes at once,
// and one that partitions them: the children's boxes come from the bins and their centre bounds
// from the partition, so no pass only recomputes bounds. Triangles travel as records (box, centre,
// index) that the partition moves, so that passes read memory in order. Boxes grow by plain
// comparisons, vectorized (a triangle's own box takes std::fmin's and std::fmax's answers, NaN
// ignored included): a library call per comparison was most of the time of the previous build,
// which took 4 times as long for the same hierarchy (the same splits, leaf order and boxes; only
// a box bound that is zero may have the other sign, which no query can tell).
#include "frep/mesh/bvh.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <utility>

#include "frep/error.hpp"

namespace frep {
namespace {

// v rounded to a float below it (down) or above it (up), as std::nextafter from the nearest
// float would give it, without a branch (which side the nearest float falls on is a coin toss, and
// every box bound takes one): a float's bits, read as an integer, step by one to the next float
// of larger magnitude (+1) or smaller (-1) on its side of zero. The nearest float has the sign of
// v, so stepping towards zero never crosses it; a NaN stays NaN.
inline float down(double v) {
  const float f = static_cast<float>(v);
  const auto u = std::bit_cast<std::uint32_t>(f);
  const std::uint32_t step = (u >> 31) ? 1u : ~0u;  // below: larger magnitude if negative
  return std::bit_cast<float>(u + (double(f) > v ? step : 0u));
}
inline float up(double v) {
  const float f = static_cast<float>(v);
  const auto u = std::bit_cast<std::uint32_t>(f);
  const std::uint32_t step = (u >> 31) ? ~0u : 1u;  // above: larger magnitude if positive
  return std::bit_cast<float>(u + (double(f) < v ? step : 0u));
}

// A box in double precision as six numbers that only ever decrease: lo xyz and -hi xyz (negation
// is exact), so that growing a box is six minimums, which the compiler makes vector instructions.
// Empty: all +inf.
struct Span {
  double v[6] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};

  double lo(int k) const { return v[k]; }
  double hi(int k) const { return -v[3 + k]; }
  void add(const double* __restrict w) {
    double* __restrict d = v;  // `w` is never this box: without aliasing, the loop vectorizes
    for (int k = 0; k < 6; ++k) d[k] = w[k] < d[k] ? w[k] : d[k];
  }
  void add(const Span& s) { add(s.v); }
  // Half the surface area (what the SAH compares).
  double area() const {
    const double dx = hi(0) - lo(0), dy = hi(1) - lo(1), dz = hi(2) - lo(2);
    return dx * dy + dy * dz + dz * dx;
  }
};

// Bounds of points (the triangles' box centres).
struct Bounds {
  double lo[3] = {INFINITY, INFINITY, INFINITY};
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY};

  void add(const double* __restrict c) {
    double* __restrict l = lo;  // as in Span::add
    double* __restrict h = hi;
    for (int k = 0; k < 3; ++k) {
      l[k] = c[k] < l[k] ? c[k] : l[k];
      h[k] = c[k] > h[k] ? c[k] : h[k];
    }
  }
};

// One triangle during the build: its box (as a Span's numbers), the box's centre (what is binned)
// and its index.
struct Prim {
  double box[6], c[3];
  std::uint32_t id;
  std::uint8_t bin[3];  // its bin on each axis in the node being split (with few enough bins)
};

struct alignas(64) Bin {  // a power of two: a bin's address is a shift
  Span box;
  std::uint32_t count = 0;
};

// Node boxes rounded outward to single precision.
void set_box(TriangleBvh::Node& n, const Span& s) {
  for (int k = 0; k < 3; ++k) {
    n.lo[k] = down(s.lo(k));
    n.hi[k] = up(s.hi(k));
  }
}

// The boxes and centre bounds of prims [b, e), for the rare splits that do not come from bins.
void bound(const Prim* p, std::uint32_t b, std::uint32_t e, Span& box, Bounds& centres) {
  for (std::uint32_t i = b; i < e; ++i) {
    box.add(p[i].box);
    centres.add(p[i].c);
  }
}

struct Builder {
  Prim* p;         // the triangles, reordered into leaf order
  std::uint32_t n;  // how many
  const BvhOptions& opt;
  std::vector<TriangleBvh::Node>& nodes;

  void build() {
    struct Task {
      std::uint32_t node, begin, end, depth;
      Span box;        // of the task's triangles
      Bounds centres;  // of their box centres
    };
    Task root{0, 0, n, 0, {}, {}};
    bound(p, root.begin, root.end, root.box, root.centres);
    std::vector<Task> stack{root};
    nodes.push_back({});
    const int bins = std::max(2, opt.bins);
    const auto leaf_size = static_cast<std::uint32_t>(std::max(1, opt.max_leaf_size));
    // Per axis: the bins (empty between nodes: a node clears the ones it filled) and the list of
    // its non-empty ones. Allocated once for the whole build.
    std::vector<Bin> bin_store(3 * static_cast<std::size_t>(bins));
    std::vector<int> used_store(3 * static_cast<std::size_t>(bins));
    Bin* bin[3];
    int* used[3];
    int used_count[3];
    for (int a = 0; a < 3; ++a) bin[a] = bin_store.data() + a * bins, used[a] = used_store.data() + a * bins;
    std::vector<double> right_area(bins);
    std::vector<std::uint32_t> right_count(bins);
    while (!stack.empty()) {
      const Task t = stack.back();
      stack.pop_back();
      set_box(nodes[t.node], t.box);
      const std::uint32_t count = t.end - t.begin;
      if (count <= leaf_size) {
        nodes[t.node].index = t.begin;
        nodes[t.node].count = count;
        continue;
      }
      const double* cl = t.centres.lo;
      const double* ch = t.centres.hi;
      Span lbox, rbox;
      Bounds lcent, rcent;
      // Without a plane (all centres coincide) the split is by index; deep nodes split at the
      // object median.
      std::uint32_t mid = t.begin + count / 2;
      bool bounded = false;  // lbox ... rcent already hold the two sides' bounds
      if (t.depth >= 40) {
        // Deep enough: object median on the widest centroid axis keeps the depth logarithmic
        // (queries use fixed-size stacks).
        const double ex = ch[0] - cl[0], ey = ch[1] - cl[1], ez = ch[2] - cl[2];
        const int axis = ex >= ey && ex >= ez ? 0 : (ey >= ez ? 1 : 2);
        std::nth_element(p + t.begin, p + mid, p + t.end,
                         [axis](const Prim& x, const Prim& y) { return x.c[axis] < y.c[axis]; });
      } else {
        // Bin on the three axes in one pass. An axis whose centres coincide (or span so little
        // that the scale overflows) gets scale 0, every triangle in bin 0, and is no candidate.
        double scale[3];
        bool live[3];
        for (int a = 0; a < 3; ++a) {
          const double extent = ch[a] - cl[a];
          live[a] = extent > 0 && bins / extent < INFINITY;
          scale[a] = live[a] ? bins / extent : 0;
        }
        for (std::uint32_t i = t.begin; i < t.end; ++i) {
          Prim& q = p[i];
          for (int a = 0; a < 3; ++a) {
            const int k = std::min(bins - 1, static_cast<int>((q.c[a] - cl[a]) * scale[a]));
            q.bin[a] = static_cast<std::uint8_t>(k);
            ++bin[a][k].count;
            bin[a][k].box.add(q.box);
          }
        }
        // The SAH cost of the planes between bins: count times area on each side. Only a plane
        // right after a non-empty bin is costed: one after an empty bin costs exactly what the
        // plane before that bin costs, and loses the tie (most bins of small nodes are empty).
        int best_axis = -1, best_bin = -1;
        double best_cost = INFINITY;
        for (int a = 0; a < 3; ++a) {
          int nu = 0;
          for (int b = 0; b < bins; ++b)
            if (bin[a][b].count) used[a][nu++] = b;
          used_count[a] = nu;
          if (!live[a]) continue;
          Span r;
          std::uint32_t rc = 0;
          for (int u = nu - 1; u > 0; --u) {
            const Bin& b = bin[a][used[a][u]];
            r.add(b.box), rc += b.count;
            right_area[u] = r.area();
            right_count[u] = rc;
          }
          Span l;
          std::uint32_t lc = 0;
          for (int u = 0; u + 1 < nu; ++u) {
            const Bin& b = bin[a][used[a][u]];
            l.add(b.box), lc += b.count;
            const double cost = lc * l.area() + right_count[u + 1] * right_area[u + 1];
            if (cost < best_cost) best_cost = cost, best_axis = a, best_bin = used[a][u] + 1;
          }
        }
        if (best_axis >= 0) {
          const int a = best_axis;
          for (int u = 0; u < used_count[a]; ++u) (used[a][u] < best_bin ? lbox : rbox).add(bin[a][used[a][u]].box);
          // Hoare's partition (the exchanges std::partition makes), which tests every prim once:
          // each side's centre bounds are gathered as it is tested.
          const auto left = [&](const Prim& q) {
            const int k = bins <= 256 ? q.bin[a] : std::min(bins - 1, static_cast<int>((q.c[a] - cl[a]) * scale[a]));
            const bool is_left = k < best_bin;
            (is_left ? lcent : rcent).add(q.c);
            return is_left;
          };
          Prim* first = p + t.begin;
          Prim* last = p + t.end;
          for (;;) {
            while (first != last && left(*first)) ++first;
            if (first == last) break;
            --last;
            while (first != last && !left(*last)) --last;
            if (first == last) break;
            std::swap(*first, *last);
            ++first;
          }
          const auto m = static_cast<std::uint32_t>(first - p);
          // Both sides hold a triangle (only such planes are costed); the check keeps the depth
          // bounded whatever the rounding.
          if (m != t.begin && m != t.end) mid = m, bounded = true;
          else lbox = rbox = Span{}, lcent = rcent = Bounds{};
        }
        for (int a = 0; a < 3; ++a)
          for (int u = 0; u < used_count[a]; ++u) bin[a][used[a][u]] = {};
      }
      if (!bounded) {
        bound(p, t.begin, mid, lbox, lcent);
        bound(p, mid, t.end, rbox, rcent);
      }
      const auto left = static_cast<std::uint32_t>(nodes.size());
      nodes[t.node].index = left;
      nodes[t.node].count = 0;
      nodes.push_back({});
      nodes.push_back({});
      stack.push_back({left + 1, mid, t.end, t.depth + 1, rbox, rcent});
      stack.push_back({left, t.begin, mid, t.depth + 1, lbox, lcent});
    }
  }
};

}  // namespace

TriangleBvh::TriangleBvh(const TriMesh& mesh, const BvhOptions& options) {
  const std::size_t n = mesh.triangles.size();
  if (n == 0) return;
  FREP_ASSERT(n < 0x7fffffffu, "too many triangles for the BVH");
  // Not value-initialized: every field is written below.
  const std::unique_ptr<Prim[]> prims(new Prim[n]);
  for (std::size_t t = 0; t < n; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &p0 = mesh.vertices[tri[0]], &p1 = mesh.vertices[tri[1]], &p2 = mesh.vertices[tri[2]];
    Prim& q = prims[t];
    for (int k = 0; k < 3; ++k) {
      const double lo = fmin_inline(fmin_inline(p0[k], p1[k]), p2[k]);
      const double hi = fmax_inline(fmax_inline(p0[k], p1[k]), p2[k]);
      q.box[k] = lo;
      q.box[3 + k] = -hi;
      q.c[k] = (lo + hi) * 0.5;
    }
    q.id = static_cast<std::uint32_t>(t);
  }
  nodes_.reserve(2 * n / std::max(1, options.max_leaf_size) + 8);
  Builder{prims.get(), static_cast<std::uint32_t>(n), options, nodes_}.build();
  order_.resize(n);
  tri_box_.resize(6 * n);
  for (std::size_t i = 0; i < n; ++i) {
    order_[i] = prims[i].id;
    for (int k = 0; k < 3; ++k) {
      tri_box_[6 * i + k] = down(prims[i].box[k]);
      tri_box_[6 * i + 3 + k] = up(-prims[i].box[3 + k]);
    }
  }
}

}  // namespace frep
