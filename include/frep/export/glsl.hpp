// Export an expression as GLSL: a function `float sdf(vec3 p)`, and a ready-to-paste Shadertoy
// fragment shader that ray-marches it.
#pragma once

#include <ostream>
#include <string>

#include "frep/expr/graph.hpp"

namespace frep {

struct GlslOptions {
  // Name of the generated function `float NAME(vec3 p)`; a GLSL identifier other than p.
  std::string function_name = "sdf";
  // Where the expression came from, quoted in the opening comment (e.g. the input file name).
  std::string source;
  // Write the frep_* helper functions the expression needs. Turn off to put several exported
  // functions into one shader: write the helpers once with write_glsl_helpers.
  bool helpers = true;
  // min, max and compare return NaN when an argument is NaN, as in frep. Without the checks
  // they use GLSL's min and max, which give frep's result for every other input (ties between
  // +0 and -0 included) and compile about 3 times faster on large expressions.
  bool nan_checks = true;
  // Mesh oracles as their closed form (~75 nodes per triangle) instead of data plus a loop.
  bool closed_form = false;
};

// Writes every frep_* helper function (frep's semantics of min, max, compare, mod, round, and,
// or, not and square in GLSL).
void write_glsl_helpers(std::ostream& out, bool nan_checks = true);

// Writes helper functions (only those the expression needs, prefixed frep_) and the function.
// Shared subexpressions become locals. Needs GLSL 3.30 or GLSL ES 3.00 and later (isnan, trunc,
// uintBitsToFloat); no #version line, so it can be pasted into any such shader. On an IEEE-754
// implementation the result equals frep's f32 evaluator except `mod`, which GLSL cannot do
// exactly (see docs/export.md); GPUs may flush denormals, skip NaN and compute sin, exp, ... with
// less precision. Iterative: fine for million-node inputs, but GPU compilers are not.
// Mesh oracles (moved or not) are written once per mesh as constant arrays (vertices, triangles,
// a bounding-box hierarchy, pseudonormals) with a function that walks the hierarchy in float;
// opt.closed_form writes their closed form instead. Other oracles are written as closed forms.
// Throws InputError if the function name is not a valid identifier, or if the meshes are too big
// for constant arrays (more than 64 KB, about 1,900 triangles: GPU compilers choke on more) or
// beyond float's range.
void write_glsl(std::ostream& out, const Graph& g, NodeId root, const GlslOptions& opt = {});

struct ShadertoyOptions {
  // Without NaN checks by default: a picture does not need them, and the shader compiles faster.
  ShadertoyOptions() { glsl.nan_checks = false; }
  GlslOptions glsl;  // the function (name, NaN checks, closed_form for meshes)
  // The shape is assumed to lie in the cube [-radius, radius]^3: rays are marched inside it and
  // the camera frames it. Fidget's models live in [-1, 1]^3.
  float radius = 1.0f;
  // Sphere tracing advances by step_scale * f. Fields whose gradient is larger than 1 (most
  // models that are not exact distances) need a step below 1 or rays pass through thin parts.
  // 0 = automatic: 0.8 / (the 99th percentile of |grad f| sampled on a grid in the cube),
  // at most 1; it is written into the shader's header comment.
  float step_scale = 0.0f;
  int max_steps = 256;
  // Expressions without z are extruded into a slab |z| <= slab * radius, so 2D shapes show up.
  float slab = 0.1f;
};

// Writes a complete Shadertoy "Image" shader (mainImage, using iResolution, iTime and iMouse):
// the function above, sphere tracing with a step scale, normals by central differences and a
// key light, fill light and sky ambient. Drag the mouse to orbit. The field function is called
// from one place only, so GPU compilers see one copy of it. Throws InputError on bad options.
void write_shadertoy(std::ostream& out, const Graph& g, NodeId root, const ShadertoyOptions& opt = {});

}  // namespace frep
