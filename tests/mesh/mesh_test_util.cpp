#include "mesh_test_util.hpp"

#include <map>

namespace frep::test {

TriMesh make_fine_box(int n, Vec3 lo, Vec3 hi) {
  TriMesh m;
  std::map<std::array<int, 3>, std::uint32_t> ids;
  auto vid = [&](int i, int j, int k) {
    auto [it, fresh] = ids.try_emplace({i, j, k}, static_cast<std::uint32_t>(m.vertices.size()));
    if (fresh)
      m.vertices.push_back({lo.x + (hi.x - lo.x) * i / n, lo.y + (hi.y - lo.y) * j / n, lo.z + (hi.z - lo.z) * k / n});
    return it->second;
  };
  // For each axis and side, a grid of quads; orientation chosen so normals point outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          auto at = [&](int u, int v) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = u;
            c[(axis + 2) % 3] = v;
            return vid(c[0], c[1], c[2]);
          };
          std::uint32_t p00 = at(a, b), p10 = at(a + 1, b), p11 = at(a + 1, b + 1), p01 = at(a, b + 1);
          // (u, v, axis) is right-handed, so u x v points along +axis.
          if (side == 1) {
            m.add_triangle(p00, p10, p11, 0, 0);
            m.add_triangle(p00, p11, p01, 0, 0);
          } else {
            m.add_triangle(p00, p11, p10, 0, 0);
            m.add_triangle(p00, p01, p11, 0, 0);
          }
        }
  return m;
}

TriMesh make_sphere(int level, double r) {
  TriMesh m;
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                             {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& p : v) p = p / length(p);
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      Vec3 p = (v[a] + v[b]) * 0.5;
      v.push_back(p / length(p));
      return mid[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<Triangle> g;
    for (const Triangle& tr : f) {
      std::uint32_t a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]), c = midpoint(tr[2], tr[0]);
      g.push_back({tr[0], a, c});
      g.push_back({tr[1], b, a});
      g.push_back({tr[2], c, b});
      g.push_back({a, b, c});
    }
    f.swap(g);
  }
  for (Vec3& p : v) m.vertices.push_back(p * r);
  for (std::uint32_t i = 0; i < f.size(); ++i) m.add_triangle(f[i][0], f[i][1], f[i][2], i, 0);
  return m;
}

}  // namespace frep::test
