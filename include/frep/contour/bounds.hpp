// Where can an expression be negative? A conservative bounding box of its inside, found by
// interval arithmetic alone: an octree of interval tests over a large cube, repeated on the box
// it finds until the box stops shrinking. Used by the mesher when no bounds are given.
#pragma once

#include "frep/eval/tape.hpp"
#include "frep/expr/model.hpp"
#include "frep/math/vec.hpp"

namespace frep {

struct BoundsSearchOptions {
  double limit = 1e4;   // search the cube [-limit, limit]^3
  int cells = 64;       // cells per axis of each round's octree (a power of 4 times 1, 4 or 16 works best)
  int max_rounds = 12;  // rounds of zooming in on the box found
  double converged = 0.01;  // stop once no side moves by more than this fraction of the extent
  int threads = 0;      // 0 = all cores
  double lipschitz = 0;  // known bound L on |f(p) - f(q)| / |p - q| (1 for exact distances, as frep convert writes); 0 = unknown
};

struct BoundsResult {
  Box3 box;          // contains every point where the expression may be < 0 (or NaN boxes)
  bool empty = false;  // the expression is >= 0 everywhere in the search cube: no box
  int rounds = 0;
};

// Throws InputError if the inside may reach the search cube's boundary (an unbounded field: a
// half-space, a 2D expression extruded along z, a periodic lattice...), asking for explicit bounds.
BoundsResult find_bounds(const Tape& tape, const BoundsSearchOptions& options = {});

// The region to work on for a field: its known box (FieldInfo::bounds) if it has one, else the
// interval search's (with info's Lipschitz bound when the options give none). Throws InputError
// (without a file name) when the field is unbounded, or positive everywhere (nothing inside).
Box3 field_region(const Tape& tape, const FieldInfo& info, const BoundsSearchOptions& options = {});

// For a result whose inside should lie in `grown` (an input's box grown by what an operation
// adds, when the input's FieldInfo::growth is unknown): `grown` widened by 0.3% of its diagonal
// if interval arithmetic proves the result positive on that box's boundary, else empty. Exact
// distances pass; a field that only bounds the distance from below can reach farther and fails.
Box3 checked_bounds(const Tape& result, const Box3& grown);

}  // namespace frep
