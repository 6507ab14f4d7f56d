// Export an expression as a plain C99 function for embedding: `float NAME(float x, float y,
// float z)`, <math.h> only, with the same semantics as frep's f32 point evaluator.
#pragma once

#include <ostream>
#include <string>

#include "frep/expr/graph.hpp"

namespace frep {

struct CExportOptions {
  // Name of the generated function; must be a C identifier other than x, y, z.
  std::string function_name = "frep_sdf";
  // Where the expression came from, quoted in the opening comment (e.g. the input file name).
  std::string source;
  // Mesh oracles as their closed form (~75 nodes per triangle) instead of data plus a loop.
  bool closed_form = false;
};

// Writes a self-contained C99 translation unit (or header): `static inline` helpers for the ops
// C has no operator for (min, max, compare, mod, and, or, not, square), inside an include guard
// so that several exported files can share one translation unit, then the function. Shared
// subexpressions become `const float` locals. Results are bit-identical to PointEvaluator when
// compiled without FMA contraction (-ffp-contract=off, no -ffast-math) and linked against the
// same libm as frep (sin, exp, ... come from libm). Iterative: fine for million-node inputs.
// Mesh oracles (frep/convert/mesh_oracle.hpp, moved or not) are written once per mesh as data (its
// vertices, triangles, a bounding-box hierarchy, pseudonormals) with a function that computes
// their exact signed distance in double by walking the hierarchy, as MeshOracle does; each
// oracle node calls it (opt.closed_form: their closed form instead). Other oracles are written
// as their closed forms. Throws InputError if the function name is not a valid identifier.
void write_c(std::ostream& out, const Graph& g, NodeId root, const CExportOptions& opt = {});

}  // namespace frep
