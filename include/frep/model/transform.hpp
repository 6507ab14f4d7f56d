// Moving, scaling, rotating, mirroring, revolving and extruding fields, as Fidget's shape library
// defines them: each is a substitution of x, y, z (frep/expr/remap.hpp). Affine ones compose, so
// a chain of transforms remaps the original shape once. Each carries the facts (FieldInfo).
#pragma once

#include "frep/math/affine.hpp"
#include "frep/math/vec.hpp"
#include "frep/model/field.hpp"

namespace frep {

// f(m(p)): the field seen through the map m (the shape moves by m's inverse). Composes with the
// affine transform that made f, if any; oracles (mesh leaves) are composed with the map.
Field transform(const Field& f, const Affine3& m);
// The shape moved by `offset`: f(p - offset).
Field move(const Field& f, const Vec3& offset);
// The shape scaled by s per axis about the origin: f(p / s).
Field scale(const Field& f, const Vec3& s);
// The shape rotated by `degrees` about `axis` (a unit vector) through `center`, right-handed.
Field rotate(const Field& f, const Vec3& axis, double degrees, const Vec3& center = {0, 0, 0});
// The shape mirrored in the plane dot(axis, p) = offset (axis a unit vector).
Field reflect(const Field& f, const Vec3& axis, double offset = 0);
// The xy section revolved about the y axis: the shape moved by `offset` along x, x replaced by
// sqrt(x^2 + y^2), moved back (Fidget's revolve_y, formula for formula).
Field revolve_y(const Field& f, double offset = 0);
// The shape's z = 0 section extruded from z = lower to z = upper.
Field extrude_z(const Field& f, double lower, double upper);
// Blended linearly from a's z = 0 section at z = lower to b's at z = upper, cut there.
Field loft_z(const Field& a, const Field& b, double lower, double upper);
// f(X, Y, Z) for any expressions X, Y, Z of f's graph. No facts survive unless X, Y, Z are
// affine (then as transform()). Throws InputError if f holds an oracle and the map is not affine.
Field remap(const Field& f, Expr X, Expr Y, Expr Z);

}  // namespace frep
