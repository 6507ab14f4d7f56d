// A bounding volume hierarchy over a mesh's triangles (binned surface-area heuristic). Boxes are
// stored in single precision rounded outward, so they always contain their double triangles.
// The one hierarchy of the project: mesh distances, the validator's intersection test and the
// mesh-to-mesh queries (mesh_pair) all build this one; its build is a few tens of milliseconds
// per 100,000 triangles.
#pragma once

#include <cstdint>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep {

struct BvhOptions {
  int max_leaf_size = 4;  // a node with at most this many triangles becomes a leaf
  int bins = 16;          // SAH candidate split planes per axis and node
};

class TriangleBvh {
 public:
  struct Node {
    float lo[3], hi[3];
    // Inner node (count == 0): children are nodes `index` and `index + 1`.
    // Leaf (count > 0): triangles order()[index .. index + count).
    std::uint32_t index;
    std::uint32_t count;
    bool leaf() const { return count != 0; }
  };

  TriangleBvh() = default;
  // Builds over every triangle of `mesh`. An empty mesh gives an empty hierarchy.
  explicit TriangleBvh(const TriMesh& mesh, const BvhOptions& options = {});

  const std::vector<Node>& nodes() const { return nodes_; }
  // Triangle indices of the mesh in leaf order.
  const std::vector<std::uint32_t>& order() const { return order_; }
  bool empty() const { return nodes_.empty(); }
  // The box of the triangle at leaf position i (triangle order()[i]): lo xyz, then hi xyz, in
  // single precision rounded outward.
  const float* triangle_box(std::uint32_t i) const { return &tri_box_[6 * std::size_t(i)]; }

  // Which node of a pair a dual traversal opens: the one that is not a leaf, or the bigger (by the
  // sum of its box's sides). Every traversal of two nodes at a time opens by this rule.
  static bool open_first(const Node& a, const Node& b) {
    const auto extent = [](const Node& n) { return (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2]); };
    return !a.leaf() && (b.leaf() || extent(a) >= extent(b));
  }
  // True if the closed boxes of two nodes share a point.
  static bool boxes_overlap(const Node& a, const Node& b) { return overlap(a.lo, a.hi, b.lo, b.hi); }

  // Calls f(a, b) once for every unordered pair of distinct triangles (a != b) whose boxes
  // overlap (closed boxes: touching counts). Single-threaded; `f` may be any callable.
  template <class F>
  void for_each_overlapping_pair(F&& f) const;

  // The same pairs, split into independent jobs: f is called with (a, b) from up to `threads`
  // threads (0: all cores; fewer if there are fewer jobs or threads cannot be started), each
  // with its own worker index (< threads) as a third argument. Which worker sees which pair
  // varies from run to run. An exception thrown by f is rethrown once all workers are done.
  template <class F>
  void for_each_overlapping_pair_parallel(int threads, F&& f) const;

  // Calls f(i, j) once for every pair of a triangle below node `a` of this hierarchy and one below
  // node `b` of `other` whose boxes overlap (closed boxes), with their leaf positions: triangles
  // order()[i] and other.order()[j]. `other` may be this hierarchy (then a and b should not be
  // the same node or nest, or pairs repeat). Single-threaded; split the work over node pairs to
  // run it in parallel.
  template <class F>
  void for_each_overlapping_pair_below(std::uint32_t a, const TriangleBvh& other, std::uint32_t b, F&& f) const {
    leaf_pairs_below(*this, a, other, b, f);
  }

  // Calls f(t) for every triangle t whose box meets the closed box `box` (boxes are outward
  // rounded: a superset of the triangles that meet it). Single-threaded.
  template <class F>
  void for_each_meeting(const Box3& box, F&& f) const;

 private:
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;
  std::vector<float> tri_box_;  // per triangle (leaf order): lo xyz, hi xyz

  static bool overlap(const float* alo, const float* ahi, const float* blo, const float* bhi) {
    return alo[0] <= bhi[0] && blo[0] <= ahi[0] && alo[1] <= bhi[1] && blo[1] <= ahi[1] && alo[2] <= bhi[2] &&
           blo[2] <= ahi[2];
  }
  template <class F>
  static void leaf_pairs_below(const TriangleBvh& ta, std::uint32_t a, const TriangleBvh& tb, std::uint32_t b, F& f);
  template <class F>
  void pairs_below(std::uint32_t a, std::uint32_t b, F& f) const {
    auto g = [&](std::uint32_t i, std::uint32_t j) { f(order_[i], order_[j]); };
    leaf_pairs_below(*this, a, *this, b, g);
  }
  template <class F>
  void pairs_within(std::uint32_t n, F& f) const;
};

template <class F>
void TriangleBvh::leaf_pairs_below(const TriangleBvh& ta, std::uint32_t a, const TriangleBvh& tb, std::uint32_t b,
                                   F& f) {
  const Node& A = ta.nodes_[a];
  const Node& B = tb.nodes_[b];
  if (!boxes_overlap(A, B)) return;
  if (A.leaf() && B.leaf()) {
    for (std::uint32_t i = A.index; i < A.index + A.count; ++i) {
      const float* bi = ta.triangle_box(i);
      for (std::uint32_t j = B.index; j < B.index + B.count; ++j) {
        const float* bj = tb.triangle_box(j);
        if (overlap(bi, bi + 3, bj, bj + 3)) f(i, j);
      }
    }
    return;
  }
  if (open_first(A, B)) {
    leaf_pairs_below(ta, A.index, tb, b, f);
    leaf_pairs_below(ta, A.index + 1, tb, b, f);
  } else {
    leaf_pairs_below(ta, a, tb, B.index, f);
    leaf_pairs_below(ta, a, tb, B.index + 1, f);
  }
}

template <class F>
void TriangleBvh::pairs_within(std::uint32_t n, F& f) const {
  const Node& N = nodes_[n];
  if (N.leaf()) {
    for (std::uint32_t i = N.index; i < N.index + N.count; ++i)
      for (std::uint32_t j = i + 1; j < N.index + N.count; ++j)
        if (overlap(&tri_box_[6 * i], &tri_box_[6 * i + 3], &tri_box_[6 * j], &tri_box_[6 * j + 3]))
          f(order_[i], order_[j]);
    return;
  }
  pairs_within(N.index, f);
  pairs_within(N.index + 1, f);
  pairs_below(N.index, N.index + 1, f);
}

template <class F>
void TriangleBvh::for_each_overlapping_pair(F&& f) const {
  if (!nodes_.empty()) pairs_within(0, f);
}

template <class F>
void TriangleBvh::for_each_meeting(const Box3& box, F&& f) const {
  if (nodes_.empty()) return;
  const auto meets = [&](const float* lo, const float* hi) {
    return Box3{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}.meets(box);
  };
  // Queries are many and small (one per triangle of a mesh, in the validator and the flat
  // merge): the stack lives on the call's frame up to 64 levels, and spills to the heap deeper.
  std::uint32_t fixed[64];
  std::size_t top = 0;
  std::vector<std::uint32_t> spill;
  const auto push = [&](std::uint32_t i) {
    if (top < 64) fixed[top++] = i;
    else spill.push_back(i);
  };
  push(0);
  while (top > 0 || !spill.empty()) {
    std::uint32_t i;
    if (!spill.empty()) i = spill.back(), spill.pop_back();
    else i = fixed[--top];
    const Node& n = nodes_[i];
    if (!meets(n.lo, n.hi)) continue;
    if (!n.leaf()) {
      push(n.index);
      push(n.index + 1);
      continue;
    }
    for (std::uint32_t i = n.index; i < n.index + n.count; ++i)
      if (meets(&tri_box_[6 * i], &tri_box_[6 * i + 3])) f(order_[i]);
  }
}

}  // namespace frep

#include "frep/util/thread_pool.hpp"

namespace frep {

template <class F>
void TriangleBvh::for_each_overlapping_pair_parallel(int threads, F&& f) const {
  if (nodes_.empty()) return;
  // Jobs: the "within" and "between" sub-problems near the root, found by expanding the top of
  // the recursion breadth-first until there are enough of them; handed out round-robin.
  struct Job {
    std::uint32_t a, b;
    bool within;
  };
  std::vector<Job> jobs{{0, 0, true}};
  const std::size_t want = 64 * static_cast<std::size_t>(resolve_thread_count(threads));
  for (std::size_t round = 0; round < 8 && jobs.size() < want; ++round) {
    std::vector<Job> next;
    for (const Job& j : jobs) {
      const Node& A = nodes_[j.a];
      if (j.within && !A.leaf()) {
        next.push_back({A.index, A.index, true});
        next.push_back({A.index + 1, A.index + 1, true});
        next.push_back({A.index, A.index + 1, false});
      } else if (!j.within) {
        const Node& B = nodes_[j.b];
        if (!boxes_overlap(A, B)) continue;
        if (!A.leaf()) {
          next.push_back({A.index, j.b, false});
          next.push_back({A.index + 1, j.b, false});
        } else if (!B.leaf()) {
          next.push_back({j.a, B.index, false});
          next.push_back({j.a, B.index + 1, false});
        } else {
          next.push_back(j);
        }
      } else {
        next.push_back(j);
      }
    }
    jobs.swap(next);
  }
  // Jobs go to a pool of at most `threads` workers (no more than there are jobs); an exception
  // thrown by f stops handing out jobs and is rethrown here.
  parallel_for_ranges(threads, jobs.size(), 1, [&](int worker, std::size_t b, std::size_t e) {
    auto g = [&](std::uint32_t a, std::uint32_t c) { f(a, c, worker); };
    for (std::size_t k = b; k < e; ++k) {
      if (jobs[k].within) pairs_within(jobs[k].a, g);
      else pairs_below(jobs[k].a, jobs[k].b, g);
    }
  });
}

}  // namespace frep
