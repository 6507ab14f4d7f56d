// The edge frame of two unit gradient fields A and B (docs/ugf.md, "The edge frame"): the sum and
// difference fields S = A + B and D = A - B, whose gradients are perpendicular, normalized to
// Sn = S / |grad S| and Dn = D / |grad D|. For planes, (Sn, Dn) are orthonormal coordinates of
// the cross-section around the edge: A = Sn cos(phi/2) + Dn sin(phi/2), B = Sn cos(phi/2) -
// Dn sin(phi/2), with phi the angle between the outward normals. Chamfers, rounds and pencils
// are written in this frame.
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf {

struct EdgeOptions {
  // Edges whose normals are closer than this to parallel (phi below it) or to opposite (phi above
  // 180 degrees minus it) are degenerate: |grad D| or |grad S| vanishes, Sn or Dn is undefined,
  // and the edge operations fall back to max(A, B) (intersections) or min(A, B) (unions). At
  // 1 degree, f32 rounding of c = cos(phi) costs about 1e-3 relative in sin(phi/2).
  float min_angle_degrees = 1.0f;
};

struct EdgeFrame {
  Expr A, B;
  Expr c;         // dot(grad A, grad B) = cos(phi), from the symbolic gradient
  Expr cos_half;  // cos(phi/2) = sqrt((1 + c) / 2) = |grad S| / 2
  Expr sin_half;  // sin(phi/2) = sqrt((1 - c) / 2) = |grad D| / 2
  Expr S, D;      // A + B and A - B
  Expr Sn, Dn;    // S / (2 cos(phi/2)) and D / (2 sin(phi/2)); finite everywhere (floored
                  // denominators) but meaningful only where `valid`
  Expr valid;     // non-zero where min_angle < phi < 180 degrees - min_angle
  float guard;    // sin(min_angle / 2): the floor of cos_half and sin_half in divisions
};

// Builds the frame; c comes from the symbolic gradients of A and B (derivative.hpp), which
// assumes |grad A| = |grad B| = 1.
EdgeFrame edge_frame(Expr A, Expr B, const EdgeOptions& opt = {});

}  // namespace frep::ugf
