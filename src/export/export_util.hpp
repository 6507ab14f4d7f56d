// Private helpers shared by the exporters: shortest round-trip float text, per-node use counts
// and identifier checks.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "frep/expr/graph.hpp"

namespace frep::export_detail {

// The shortest decimal text that reads back as exactly `v` (std::to_chars), e.g. "0.1", "1e-05",
// "-3", "inf", "-nan". Callers turn it into their language's literal.
inline std::string shortest_float(float v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// How often each node is an argument of a node reachable from `root` (the root counts once).
// Indexed by node id, size root + 1. `order` is reachable_nodes(g, root).
inline std::vector<std::uint32_t> use_counts(const Graph& g, const std::vector<NodeId>& order, NodeId root) {
  std::vector<std::uint32_t> uses(root + 1, 0);
  for (NodeId id : order) {
    const Node& n = g.node(id);
    if (n.a != kNoNode) ++uses[n.a];
    if (n.b != kNoNode) ++uses[n.b];
  }
  ++uses[root];
  return uses;
}

// Text for a one-line comment in any of the output languages: control characters (a newline
// would end a // or % comment) become spaces, and "*/" (which would end a C comment) "* /".
inline std::string comment_text(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '/' && !out.empty() && out.back() == '*') out += ' ';
    out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
  }
  return out;
}

// [A-Za-z_][A-Za-z0-9_]*: a valid name in C and GLSL (keywords are the caller's problem).
inline bool is_identifier(std::string_view s) {
  if (s.empty()) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    if (!alpha && !(i > 0 && c >= '0' && c <= '9')) return false;
  }
  return true;
}

// Words a generated function may not be called: C and GLSL keywords and type names (a function
// named `int` or `float` does not compile), and the helpers the exports write themselves (frep_*).
enum class Language { C, Glsl };

inline bool is_reserved_name(std::string_view s, Language lang) {
  static constexpr std::string_view kReserved[] = {
      // C (C99 to C23)
      "auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum", "extern",
      "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return", "short", "signed",
      "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void", "volatile", "while", "bool",
      "true", "false", "alignas", "alignof", "constexpr", "nullptr", "static_assert", "thread_local", "typeof",
      "_Bool", "_Complex", "_Imaginary", "_Alignas", "_Alignof", "_Atomic", "_Generic", "_Noreturn",
      "_Static_assert", "_Thread_local", "main",
      // GLSL
      "attribute", "uniform", "varying", "buffer", "shared", "coherent", "readonly", "writeonly", "layout",
      "centroid", "flat", "smooth", "noperspective", "patch", "sample", "subroutine", "in", "out", "inout",
      "invariant", "precise", "discard", "lowp", "mediump", "highp", "precision", "struct", "uint", "vec2", "vec3",
      "vec4", "ivec2", "ivec3", "ivec4", "uvec2", "uvec3", "uvec4", "bvec2", "bvec3", "bvec4", "dvec2", "dvec3",
      "dvec4", "mat2", "mat3", "mat4", "sampler2D", "sampler3D", "samplerCube", "mainImage", "auto_step_scale"};
  // Functions and macros of <math.h> (also with their f and l suffixes) for C, GLSL's built-in
  // functions for GLSL: the generated code calls them, or a function of that name would clash.
  static constexpr std::string_view kCMath[] = {
      "acos", "acosh", "asin", "asinh", "atan", "atan2", "atanh", "cbrt", "ceil", "copysign", "cos", "cosh", "erf",
      "erfc", "exp", "exp2", "expm1", "fabs", "fdim", "floor", "fma", "fmax", "fmin", "fmod", "frexp", "hypot",
      "isfinite", "isinf", "isnan", "isnormal", "ldexp", "lgamma", "log", "log10", "log1p", "log2", "modf", "nan",
      "nearbyint", "pow", "remainder", "rint", "round", "signbit", "sin", "sinh", "sqrt", "tan", "tanh", "tgamma",
      "trunc", "NAN", "INFINITY", "HUGE_VAL", "HUGE_VALF", "M_PI", "fpclassify", "abs"};
  static constexpr std::string_view kGlslBuiltins[] = {
      "abs", "acos", "acosh", "asin", "asinh", "atan", "atanh", "ceil", "clamp", "cos", "cosh", "cross", "degrees",
      "distance", "dot", "exp", "exp2", "faceforward", "floor", "fma", "fract", "inversesqrt", "isinf", "isnan",
      "length", "log", "log2", "max", "min", "mix", "mod", "modf", "normalize", "pow", "radians", "reflect", "refract",
      "round", "roundEven", "sign", "sin", "sinh", "smoothstep", "sqrt", "step", "tan", "tanh", "texture",
      "texelFetch", "trunc"};
  for (std::string_view r : kReserved)
    if (s == r) return true;
  if (lang == Language::C) {
    for (std::string_view r : kCMath)
      if (s == r || (s.size() == r.size() + 1 && s.substr(0, r.size()) == r && (s.back() == 'f' || s.back() == 'l')))
        return true;
  } else {
    for (std::string_view r : kGlslBuiltins)
      if (s == r) return true;
  }
  return s.rfind("frep_", 0) == 0 && s != "frep_sdf";
}

}  // namespace frep::export_detail
