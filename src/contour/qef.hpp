// The quadratic error function of dual contouring: the sum of squared distances of a point to
// the tangent planes at the surface crossings of a cell, minimized with a bias towards the mass
// point (the crossings' centroid), so that flat pieces give a point on the plane, edges a point
// on the edge line and corners the corner, and nearly parallel normals cannot throw the point far.
//
// Private to the mesher (not installed).
#pragma once

#include "frep/math/vec.hpp"

namespace frep {

class Qef {
 public:
  // A crossing at p with unit normal n (a tangent plane).
  void add(const Vec3& p, const Vec3& n);
  // A crossing without a usable normal: it only moves the mass point.
  void add_point(const Vec3& p);

  int points() const { return points_; }
  int planes() const { return planes_; }
  // Centroid of the crossings ((0,0,0) without any).
  Vec3 mass_point() const;
  // Sum of squared plane distances at x.
  double error(const Vec3& x) const;

  // The minimizer nearest the mass point, by the eigen-decomposition of A^T A: directions whose
  // eigenvalue is below `threshold` times the largest are left at the mass point (truncated
  // pseudo-inverse), and at most `max_rank` directions are solved for. `rank` receives the
  // number used.
  Vec3 solve(double threshold, int max_rank = 3, int* rank = nullptr) const;
  // Like solve(), keeping the point inside `box`: if the minimizer leaves the box grown by
  // `slack`, the QEF (plus a small pull towards the mass point) is minimized over the box instead
  // (exactly: every combination of coordinates at their bounds is tried); the result is in the box.
  Vec3 solve_in(const Box3& box, double threshold, double slack) const;

 private:
  double ata_[6] = {};  // xx xy xz yy yz zz
  double atb_[3] = {};
  double btb_ = 0;
  Vec3 mass_;
  int points_ = 0, planes_ = 0;
};

// Eigen-decomposition of a symmetric 3x3 matrix (xx xy xz yy yz zz): eigenvalues in decreasing
// order, and orthonormal eigenvectors.
void symmetric_eigen3(const double m[6], double values[3], Vec3 vectors[3]);

}  // namespace frep
