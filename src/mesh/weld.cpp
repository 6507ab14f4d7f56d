#include "frep/mesh/weld.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "frep/error.hpp"

namespace frep {
namespace {

std::uint64_t bits(double d) {
  if (d == 0) d = 0;  // -0 and +0 are the same position
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  return u;
}

std::uint64_t mix(std::uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}

// Representative (lowest index among equal positions) for each used vertex (every vertex if
// `used` is null): open addressing on the exact bit pattern, linear in the vertex count.
std::vector<std::uint32_t> exact_representatives(const std::vector<Vec3>& vertices, const char* used) {
  const std::size_t n = vertices.size();
  std::vector<std::uint32_t> rep(n, kNoVertex);
  std::size_t cap = 16;
  while (cap < 2 * n) cap <<= 1;
  std::vector<std::uint32_t> table(cap, kNoVertex);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (used && !used[i]) continue;
    const Vec3& p = vertices[i];
    std::size_t h = mix(bits(p.x) * 0x9E3779B97F4A7C15ULL ^ mix(bits(p.y)) * 3 ^ mix(bits(p.z) + 0x1234567)) & (cap - 1);
    for (;;) {
      const std::uint32_t j = table[h];
      if (j == kNoVertex) {
        table[h] = i;
        rep[i] = i;
        break;
      }
      if (vertices[j] == p) {
        rep[i] = j;
        break;
      }
      h = (h + 1) & (cap - 1);
    }
  }
  return rep;
}

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

std::vector<std::uint32_t> tolerance_representatives(const TriMesh& m, const std::vector<char>& used, double tol) {
  const std::size_t n = m.vertices.size();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  struct Key {
    std::int64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return mix(std::uint64_t(k.x) * 0x9E3779B97F4A7C15ULL ^ mix(std::uint64_t(k.y)) ^ mix(std::uint64_t(k.z) + 7));
    }
  };
  auto cell = [&](const Vec3& p, std::uint32_t i) {
    Key k;
    std::int64_t* out[3] = {&k.x, &k.y, &k.z};
    for (int c = 0; c < 3; ++c) {
      const double q = std::floor(p[c] / tol);
      if (!(std::fabs(q) < 4e18))
      {
        char buf[160];
        std::snprintf(buf, sizeof buf, "weld tolerance %g is too small for vertex %u at (%.9g, %.9g, %.9g)", tol, i,
                      p.x, p.y, p.z);
        throw InputError(m.name, 0, std::string(buf) + "; use 0 for exact welding");
      }
      *out[c] = static_cast<std::int64_t>(q);
    }
    return k;
  };
  std::unordered_map<Key, std::vector<std::uint32_t>, KeyHash> grid;
  grid.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    if (used[i]) grid[cell(m.vertices[i], i)].push_back(i);
  const double tol2 = tol * tol;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    const Key k = cell(m.vertices[i], i);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            if (j >= i || length2(m.vertices[i] - m.vertices[j]) > tol2) continue;
            const std::uint32_t a = find(parent, i), b = find(parent, j);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
          }
        }
  }
  // Make every representative the lowest index of its set.
  std::vector<std::uint32_t> lowest(n, kNoVertex), rep(n, kNoVertex);
  for (std::uint32_t i = 0; i < n; ++i)
    if (used[i]) {
      const std::uint32_t r = find(parent, i);
      if (lowest[r] == kNoVertex) lowest[r] = i;
      rep[i] = lowest[r];
    }
  return rep;
}

}  // namespace

WeldResult weld(const TriMesh& mesh, const WeldOptions& options) {
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    throw InputError(mesh.name, 0, "weld tolerance must be a finite number >= 0");
  mesh.check_consistent();
  const std::size_t n = mesh.vertices.size();
  std::vector<char> used(n, 0);
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) used[v] = 1;
  const std::vector<std::uint32_t> rep = options.tolerance > 0 ? tolerance_representatives(mesh, used, options.tolerance)
                                                                 : exact_representatives(mesh.vertices, used.data());
  WeldResult r;
  r.welded_of_original.assign(n, kNoVertex);
  std::size_t used_count = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    ++used_count;
    if (rep[i] == i) {
      r.welded_of_original[i] = static_cast<std::uint32_t>(r.mesh.vertices.size());
      r.original_of_welded.push_back(i);
      r.mesh.vertices.push_back(mesh.vertices[i]);
    }
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (used[i]) r.welded_of_original[i] = r.welded_of_original[rep[i]];
  r.merged = used_count - r.mesh.vertices.size();
  r.mesh.triangles.reserve(mesh.triangles.size());
  for (const Triangle& t : mesh.triangles)
    r.mesh.triangles.push_back({r.welded_of_original[t[0]], r.welded_of_original[t[1]], r.welded_of_original[t[2]]});
  r.mesh.origins = mesh.origins;
  r.mesh.indexed = mesh.indexed;
  r.mesh.name = mesh.name;
  return r;
}

std::vector<std::uint32_t> first_at_same_position(const std::vector<Vec3>& vertices) {
  return exact_representatives(vertices, nullptr);
}

}  // namespace frep
