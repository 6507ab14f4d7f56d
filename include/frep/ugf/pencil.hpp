// Pencils of planes through an edge (docs/ugf.md, "Pencils").
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/ugf/edge_frame.hpp"

namespace frep::ugf {

// P(theta) = Sn cos(theta) + Dn sin(theta): for planes, the signed distance to the plane through
// the edge whose normal is at angle theta from the bisector, towards A's normal. theta = phi/2
// gives A, -phi/2 gives B, 0 the symmetric chamfer direction (Sn), pi/2 the bisector plane (Dn).
// A unit gradient field wherever the frame is valid; meaningless where it is not.
Expr pencil(const EdgeFrame& f, float theta);

// A face through the edge at angle theta, moved by d along its normal (Hesse normal form):
// P(theta) - d. Exact plane distance for planar A and B.
Expr pencil_face(const EdgeFrame& f, float theta, float d);

// Any chamfer of the intersection: max(A, B, P(theta) - d); max(A, B) where the frame is not
// valid. Exact inside the solid for planes; theta = 0 with d = -h is chamfer_intersection's
// inset chamfer.
Expr pencil_chamfer(const EdgeFrame& f, float theta, float d);

}  // namespace frep::ugf
