// Helpers for the converter's tests: sample points around a mesh (uniform in its grown box,
// near the surface on both sides, exactly on vertices and edges), evaluate a converted
// expression there with pruning, and compare with the independent distance oracle.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "frep/convert/convert.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/mesh/mesh_distance.hpp"
#include "frep/mesh/weld.hpp"

namespace frep::test {

struct Samples {
  std::vector<Vec3> points;
  std::vector<const char*> kind;  // "uniform", "near", "vertex", "edge"
};

// `uniform` points in the bounding box grown by 10%; `near` points on random triangles (by area)
// moved along the normal by +-{1e-5, 1e-4, 1e-3, 1e-2} of the diagonal; every vertex (up to
// `on`) and as many points on edges (midpoints and random positions).
inline Samples sample_around(const TriMesh& mesh, std::size_t uniform, std::size_t near, std::size_t on,
                             unsigned seed = 1) {
  Samples s;
  std::mt19937_64 rng(seed);
  const Box3 box = bounding_box(mesh);
  const Vec3 size = box.size();
  const double diag = length(size);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t i = 0; i < uniform; ++i) {
    s.points.push_back({box.lo.x - 0.05 * size.x + 1.1 * size.x * u(rng), box.lo.y - 0.05 * size.y + 1.1 * size.y * u(rng),
                        box.lo.z - 0.05 * size.z + 1.1 * size.z * u(rng)});
    s.kind.push_back("uniform");
  }
  std::vector<double> cumulative;
  double total = 0;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    total += 0.5 * length(cross(mesh.corner(t, 1) - mesh.corner(t, 0), mesh.corner(t, 2) - mesh.corner(t, 0)));
    cumulative.push_back(total);
  }
  const double offsets[] = {1e-5, 1e-4, 1e-3, 1e-2};
  for (std::size_t i = 0; i < near; ++i) {
    const std::size_t t = static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) -
                                                   cumulative.begin());
    const std::size_t tt = std::min(t, mesh.num_triangles() - 1);
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 p0 = mesh.corner(tt, 0), p1 = mesh.corner(tt, 1), p2 = mesh.corner(tt, 2);
    Vec3 n = cross(p1 - p0, p2 - p0);
    const double ln = length(n);
    if (!(ln > 0)) continue;
    n = n / ln;
    const double off = offsets[i % 4] * diag * (i % 8 < 4 ? 1 : -1);
    s.points.push_back(p0 + (p1 - p0) * a + (p2 - p0) * b + n * off);
    s.kind.push_back("near");
  }
  // Vertices that triangles use (files may carry unused ones far away).
  const std::size_t step = std::max<std::size_t>(1, 3 * mesh.num_triangles() / std::max<std::size_t>(on, 1));
  for (std::size_t c = 0; c < 3 * mesh.num_triangles() && on; c += step) {
    s.points.push_back(mesh.corner(c / 3, static_cast<int>(c % 3)));
    s.kind.push_back("vertex");
  }
  for (std::size_t i = 0; i < on && mesh.num_triangles(); ++i) {
    const std::size_t t = static_cast<std::size_t>(u(rng) * static_cast<double>(mesh.num_triangles())) % mesh.num_triangles();
    const int k = static_cast<int>(i % 3);
    const Vec3 a = mesh.corner(t, k), b = mesh.corner(t, (k + 1) % 3);
    const double w = i % 2 ? 0.5 : u(rng);
    s.points.push_back(a + (b - a) * w);
    s.kind.push_back("edge");
  }
  return s;
}

struct Accuracy {
  double max_error = 0;        // largest |f - reference|, over the diagonal
  std::size_t sign_errors = 0;  // reference clearly off the surface, f of the other sign
  std::size_t nonfinite = 0;
  std::size_t count = 0;
  std::string worst;            // where the largest error was
};

// Evaluates the model in f32 (pruned, bit-identical to the full tape) and compares with the
// oracle's exact signed distance.
inline Accuracy measure(const Model& model, const TriMesh& mesh, const Samples& s) {
  const Tape tape = Tape::compile(*model.graph, model.root);
  const std::size_t n = s.points.size();
  std::vector<float> x(n), y(n), z(n), f(n);
  std::vector<double> xd(n), yd(n), zd(n), ref(n);
  for (std::size_t i = 0; i < n; ++i) {
    // The expression sees f32 coordinates: measure the oracle at the same points.
    x[i] = static_cast<float>(s.points[i].x), y[i] = static_cast<float>(s.points[i].y), z[i] = static_cast<float>(s.points[i].z);
    xd[i] = x[i], yd[i] = y[i], zd[i] = z[i];
  }
  eval_points(tape, x.data(), y.data(), z.data(), f.data(), n);
  const MeshDistance oracle(mesh);
  oracle.signed_distance(xd.data(), yd.data(), zd.data(), ref.data(), n);
  const double diag = length(bounding_box(mesh).size());
  Accuracy a;
  a.count = n;
  for (std::size_t i = 0; i < n; ++i) {
    // A point beyond f32's range (a mesh at 3.4e38 grown by 10%) is not a point the expression
    // can be asked about.
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) continue;
    if (!std::isfinite(f[i])) {
      ++a.nonfinite;
      continue;
    }
    const double err = std::fabs(f[i] - ref[i]) / diag;
    if (err > a.max_error) {
      a.max_error = err;
      a.worst = std::string(s.kind[i]) + " point (" + std::to_string(xd[i]) + ", " + std::to_string(yd[i]) + ", " +
                std::to_string(zd[i]) + "): " + std::to_string(f[i]) + " vs " + std::to_string(ref[i]);
    }
    if (std::fabs(ref[i]) > 1e-5 * diag && (f[i] < 0) != (ref[i] < 0)) ++a.sign_errors;
  }
  return a;
}

}  // namespace frep::test
