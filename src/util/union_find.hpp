// Union-find (disjoint sets) over 0..n-1 whose roots are the smallest members: the one used by
// validation (shells, planar regions, duplicate vertices), the arrangement (coplanar groups) and
// repair (fans around a vertex).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace frep {

class UnionFind {
 public:
  // n singletons.
  explicit UnionFind(std::size_t n = 0) : p_(n) { std::iota(p_.begin(), p_.end(), 0u); }
  // From given parents, each no larger than its child (a parent of itself is a root).
  explicit UnionFind(std::vector<std::uint32_t> parent) : p_(std::move(parent)) {}

  // Back to n singletons, keeping the storage.
  void reset(std::size_t n) {
    p_.resize(n);
    std::iota(p_.begin(), p_.end(), 0u);
  }
  std::size_t size() const { return p_.size(); }
  std::uint32_t find(std::uint32_t i) {
    while (p_[i] != i) i = p_[i] = p_[p_[i]];
    return i;
  }
  // Joins the sets of a and b; true if they were apart.
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    p_[std::max(a, b)] = std::min(a, b);
    return true;
  }
  // Every member's root, in the parents' own storage (a parent is never larger than its
  // child, so one increasing pass suffices).
  std::vector<std::uint32_t> roots() && {
    for (std::uint32_t& p : p_) p = p_[p];
    return std::move(p_);
  }

 private:
  std::vector<std::uint32_t> p_;
};

}  // namespace frep
