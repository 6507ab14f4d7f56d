// The GLSL and Shadertoy exporters (see include/frep/export/glsl.hpp).
#include "frep/export/glsl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "export/c_like.hpp"
#include "export/export_util.hpp"
#include "export/mesh_code.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/copy.hpp"

namespace frep {
namespace {

using export_detail::CLikeDialect;

// GLSL has no literal for infinity or NaN; the bit patterns are exact (GLSL 3.30 / ES 3.00).
std::string glsl_literal(float v) {
  if (std::isnan(v)) return "uintBitsToFloat(0x7fc00000u)";
  if (std::isinf(v)) return v < 0 ? "uintBitsToFloat(0xff800000u)" : "uintBitsToFloat(0x7f800000u)";
  std::string s = export_detail::shortest_float(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

CLikeDialect glsl_dialect() {
  CLikeDialect d;
  d.vars = {"p.x", "p.y", "p.z"};
  d.local_decl = "float ";
  d.literal = &glsl_literal;
  auto set = [&](Op op, std::string_view fn) { d.call[static_cast<int>(op)] = fn; };
  set(Op::Abs, "abs");
  set(Op::Sqrt, "sqrt");
  set(Op::Square, "frep_square");
  set(Op::Floor, "floor");
  set(Op::Ceil, "ceil");
  set(Op::Round, "frep_round");  // GLSL's round() may round halves either way
  set(Op::Sin, "sin");
  set(Op::Cos, "cos");
  set(Op::Tan, "tan");
  set(Op::Asin, "asin");
  set(Op::Acos, "acos");
  set(Op::Atan, "atan");
  set(Op::Exp, "exp");
  set(Op::Ln, "log");
  set(Op::Not, "frep_not");
  set(Op::Atan2, "atan");  // atan(y, x): frep's atan2(a, b) has y = a, x = b
  set(Op::Min, "frep_min");  // GLSL's min/max are undefined for NaN and return a on ties
  set(Op::Max, "frep_max");
  set(Op::Compare, "frep_compare");
  set(Op::Mod, "frep_mod");  // GLSL's mod() is a - b * floor(a / b): negative for b < 0
  set(Op::And, "frep_and");
  set(Op::Or, "frep_or");
  return d;
}

// One helper per opcode that needs one, written only if the expression uses that opcode.
// `fast` is the variant without NaN checks (nullptr: the same either way).
struct Helper {
  Op op;
  const char* text;
  const char* fast;
};
constexpr Helper kHelpers[] = {
    {Op::Square, "float frep_square(float a) { return a * a; }\n", nullptr},
    // a + b is NaN when either is: propagates NaN without a NaN constant. GLSL's min(x, y) is
    // y < x ? y : x, so min(b, a) is frep's a < b ? a : b, ties (+0 and -0) included.
    {Op::Min, "float frep_min(float a, float b) { return (isnan(a) || isnan(b)) ? a + b : (a < b ? a : b); }\n",
     "float frep_min(float a, float b) { return min(b, a); }\n"},
    {Op::Max, "float frep_max(float a, float b) { return (isnan(a) || isnan(b)) ? a + b : (a > b ? a : b); }\n",
     "float frep_max(float a, float b) { return max(b, a); }\n"},
    {Op::Compare,
     "float frep_compare(float a, float b) {\n"
     "  return (isnan(a) || isnan(b)) ? a + b : (a < b ? -1.0 : (a > b ? 1.0 : 0.0));\n"
     "}\n",
     "float frep_compare(float a, float b) { return a < b ? -1.0 : (a > b ? 1.0 : 0.0); }\n"},
    // Exact: a - trunc(a) is exact in f32, and ties go away from zero.
    {Op::Round, "float frep_round(float a) { float t = trunc(a); return abs(a - t) >= 0.5 ? t + sign(a) : t; }\n", nullptr},
    // Euclidean remainder in [0, |b|), up to the rounding of a / |b| (GLSL has no exact fmod).
    {Op::Mod,
     "float frep_mod(float a, float b) {\n"
     "  float m = abs(b);\n"
     "  if (isinf(m) && !isinf(a)) return a < 0.0 ? m : a;\n"
     "  float r = a - m * floor(a / m);\n"
     "  return r < 0.0 ? r + m : (r >= m ? r - m : r);\n"
     "}\n",
     nullptr},
    // NaN counts as non-zero, as in frep.
    {Op::And, "float frep_and(float a, float b) { return a == 0.0 ? a : b; }\n", nullptr},
    {Op::Or, "float frep_or(float a, float b) { return a != 0.0 ? a : b; }\n", nullptr},
    {Op::Not, "float frep_not(float a) { return a == 0.0 ? 1.0 : 0.0; }\n", nullptr},
};

const char* helper_text(const Helper& h, bool nan_checks) { return nan_checks || !h.fast ? h.text : h.fast; }

void check_name(const std::string& name) {
  if (!export_detail::is_identifier(name) || name == "p" || name.rfind("gl_", 0) == 0 ||
      name.find("__") != std::string::npos || export_detail::is_reserved_name(name, export_detail::Language::Glsl))
    throw InputError("", 0,
                     "GLSL function name '" + name +
                         "' is not a GLSL identifier, or is reserved (p, gl_*, __, a keyword or type, a built-in function, or frep_*)");
}

// The helpers, the meshes' data and code, and the function; returns the number of reachable nodes.
std::size_t write_function(std::ostream& out, const Graph& g, NodeId root, const GlslOptions& opt,
                           const std::vector<NodeId>& order, const export_detail::MeshTables& meshes) {
  const std::string& name = opt.function_name;
  const std::uint64_t ops = export_detail::ops_present(g, order);
  for (const Helper& h : kHelpers)
    if (opt.helpers && (ops & (std::uint64_t{1} << static_cast<unsigned>(h.op)))) out << helper_text(h, opt.nan_checks);
  const std::string prefix = name + "_";
  if (!meshes.empty()) export_detail::write_glsl_meshes(out, prefix, meshes);
  out << "\nfloat " << name << "(vec3 p) {\n";
  CLikeDialect dialect = glsl_dialect();
  dialect.oracle = [&](std::uint32_t i) { return prefix + "oracle" + std::to_string(i) + "(p)"; };
  export_detail::emit_c_like_body(out, g, root, order, dialect, "  ");
  out << "}\n";
  return order.size();
}

// Oracles for the data form: the closed form of everything on request, of the oracles that are
// not meshes otherwise (the data form knows only meshes). Null if `g` can be written as it is.
std::unique_ptr<Model> prepare_oracles(const Graph& g, NodeId root, bool closed_form) {
  if (!has_oracles(g, root)) return nullptr;
  if (closed_form) return std::make_unique<Model>(expand_oracles(g, root));
  if (export_detail::only_mesh_oracles(g, reachable_nodes(g, root))) return nullptr;
  return std::make_unique<Model>(export_detail::expand_other_oracles(g, root));
}

// The meshes' tables, checked for the GLSL data form (before anything is written).
export_detail::MeshTables glsl_mesh_tables(const Graph& g, const std::vector<NodeId>& order) {
  export_detail::MeshTables meshes = export_detail::mesh_tables(g, order);
  if (!meshes.empty()) export_detail::check_glsl_meshes(meshes);
  return meshes;
}

// What the opening comment says about the meshes, if there are any.
void write_mesh_note(std::ostream& out, const export_detail::MeshTables& meshes) {
  if (meshes.empty()) return;
  out << "// Mesh oracles (" << export_detail::mesh_summary(meshes)
      << ") are constant arrays plus a loop, in float:\n"
         "// their signed distance within about 1e-7 of the mesh's size plus its coordinates.\n";
}

void write_header(std::ostream& out, const std::string& what, const std::string& source, std::size_t nodes) {
  out << "// " << what << ", generated by frep export";
  if (!source.empty()) out << " from " << export_detail::comment_text(source);
  out << " (" << nodes << " nodes).\n";
}



// The ray marcher. frep_scene is the field to march (the exported function, or its extrusion
// for 2D expressions); everything else is independent of the expression. One loop does the
// marching and then the six samples of the normal, so that the field function is pasted into the
// shader once: GPU compilers take time at least linear in the code they see.
constexpr const char* kMarcher = R"(
// Entry and exit distances of the ray through the cube [-FREP_RADIUS, FREP_RADIUS]^3.
vec2 frep_box(vec3 ro, vec3 rd) {
  vec3 inv = 1.0 / rd;
  vec3 a = (vec3(-FREP_RADIUS) - ro) * inv, b = (vec3(FREP_RADIUS) - ro) * inv;
  vec3 lo = min(a, b), hi = max(a, b);
  return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
  vec2 uv = (2.0 * fragCoord - iResolution.xy) / iResolution.y;
  // Drag the mouse to orbit; otherwise the view turns slowly.
  float yaw = FREP_AUTO_YAW, pitch = 0.35;
  if (iMouse.z > 0.0) {
    yaw = 6.2831853 * (iMouse.x / iResolution.x - 0.5);
    pitch = 3.0 * (iMouse.y / iResolution.y - 0.5);
  }
  // Orbit around the y axis; at yaw = pitch = 0 the camera looks down -z with y up.
  vec3 fwd = -vec3(sin(yaw) * cos(pitch), sin(pitch), cos(yaw) * cos(pitch));
  vec3 right = normalize(cross(fwd, vec3(0.0, 1.0, 0.0)));
  vec3 up = cross(right, fwd);
  vec3 ro = -3.6 * FREP_RADIUS * fwd;
  vec3 rd = normalize(fwd + 0.5 * (uv.x * right + uv.y * up));

  vec3 col = mix(vec3(0.92, 0.94, 0.97), vec3(0.55, 0.65, 0.8), 0.5 + 0.5 * uv.y);
  vec2 span = frep_box(ro, rd);
  float t = max(span.x, 0.0);
  int hit = -1;  // the step at which the surface was reached
  vec3 p = ro, n = vec3(0.0);
  float h = 1e-3 * FREP_RADIUS;  // central-difference step
  for (int i = 0; i < FREP_MAX_STEPS + 6 && span.x < span.y; i++) {
    int k = i - hit - 1;  // after a hit: which of the six normal samples
    vec3 q = ro + t * rd;
    if (hit >= 0) {
      q = p;
      q[k / 2] += (k % 2 == 0) ? h : -h;
    }
    float d = frep_scene(q);
    if (hit < 0) {
      if (isnan(d) || t > span.y || i >= FREP_MAX_STEPS) break;
      if (d < 2e-4 * FREP_RADIUS) {  // negative: already inside (a cut at the box)
        hit = i;
        p = q;
      } else {
        t += FREP_STEP_SCALE * d;
      }
    } else {
      n[k / 2] += (k % 2 == 0) ? d : -d;
      if (k == 5) break;
    }
  }
  if (hit >= 0) {
    float len = length(n);
    n = len > 0.0 ? n / len : -rd;
    if (dot(n, rd) > 0.0) n = -n;  // cut faces at the box and fields that are not distances
    vec3 key = normalize(0.6 * right + 0.8 * up - 0.5 * fwd);
    float diffuse = max(dot(n, key), 0.0);
    float fill = max(dot(n, -fwd), 0.0);
    float spec = pow(max(dot(reflect(rd, n), key), 0.0), 32.0);
    vec3 base = vec3(0.85, 0.72, 0.55);
    col = base * (0.12 + 0.7 * diffuse + 0.25 * fill) + 0.12 * (0.5 + 0.5 * n.y) * vec3(0.55, 0.65, 0.8) + 0.25 * spec;
  }
  fragColor = vec4(pow(clamp(col, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

// A step scale for sphere tracing: 0.8 / (the 99th percentile of |grad f| on a grid in the
// cube). A percentile, not the maximum, because fields have singular points (ln near 0, kinks)
// where the gradient is huge but no ray needs to slow down. The grid shrinks for large tapes so
// that this stays under about 2e8 instruction evaluations.
float auto_step_scale(const Graph& g, NodeId root, float radius, float* p99_out) {
  const Tape tape = Tape::compile(g, root);
  const double budget = 2e8 / static_cast<double>(std::max<std::size_t>(tape.size(), 1));
  const int n = std::clamp(static_cast<int>(std::cbrt(budget)), 6, 24);
  std::vector<float> xs, ys, zs;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        // Cell centres: avoids the planes of symmetry where many models have kinks.
        auto at = [&](int t) { return radius * (-1.0f + (2.0f * static_cast<float>(t) + 1.0f) / static_cast<float>(n)); };
        xs.push_back(at(i));
        ys.push_back(at(j));
        zs.push_back(at(k));
      }
  std::vector<Grad> out(xs.size());
  GradEvaluator ev;
  ev.eval(tape, xs.data(), ys.data(), zs.data(), out.data(), xs.size());
  std::vector<float> mags;
  for (const Grad& d : out) {
    const float m = std::sqrt(d.dx * d.dx + d.dy * d.dy + d.dz * d.dz);
    if (std::isfinite(m)) mags.push_back(m);
  }
  float p99 = 1.0f;
  if (!mags.empty()) {
    const std::size_t at = std::min(mags.size() - 1, mags.size() * 99 / 100);
    std::nth_element(mags.begin(), mags.begin() + static_cast<std::ptrdiff_t>(at), mags.end());
    p99 = mags[at];
  }
  *p99_out = p99;
  if (p99 <= 0.8f) return 1.0f;
  char buf[32];  // two significant digits: it is a safety factor, and reads better
  std::snprintf(buf, sizeof buf, "%.2g", static_cast<double>(std::max(0.8f / p99, 1e-3f)));
  return std::strtof(buf, nullptr);
}

}  // namespace

void write_glsl(std::ostream& out, const Graph& g, NodeId root, const GlslOptions& opt) {
  if (const auto m = prepare_oracles(g, root, opt.closed_form)) return write_glsl(out, *m->graph, m->root, opt);
  check_name(opt.function_name);
  const std::vector<NodeId> order = reachable_nodes(g, root);
  const export_detail::MeshTables meshes = glsl_mesh_tables(g, order);
  write_header(out, "GLSL", opt.source, order.size());
  out << "// float " << opt.function_name
      << "(vec3 p): the expression's value at p, negative inside. Needs GLSL 3.30 or GLSL ES 3.00.\n"
         "// frep's semantics on IEEE-754 hardware except mod (within rounding)"
      << (opt.nan_checks ? "" : " and NaN in min/max/compare") << "; see frep's docs/export.md.\n";
  write_mesh_note(out, meshes);
  write_function(out, g, root, opt, order, meshes);
}

void write_glsl_helpers(std::ostream& out, bool nan_checks) {
  for (const Helper& h : kHelpers) out << helper_text(h, nan_checks);
}

void write_shadertoy(std::ostream& out, const Graph& g, NodeId root, const ShadertoyOptions& opt) {
  if (const auto m = prepare_oracles(g, root, opt.glsl.closed_form)) return write_shadertoy(out, *m->graph, m->root, opt);
  check_name(opt.glsl.function_name);
  if (!(opt.radius > 0 && std::isfinite(opt.radius)))
    throw InputError("", 0, "the Shadertoy radius must be a finite number > 0");
  if (!(opt.step_scale >= 0 && opt.step_scale <= 1))
    throw InputError("", 0, "the Shadertoy step scale must be in (0, 1] (or 0: automatic)");
  if (opt.max_steps < 1) throw InputError("", 0, "the Shadertoy step count must be at least 1");
  if (!(opt.slab > 0 && std::isfinite(opt.slab)))
    throw InputError("", 0, "the Shadertoy slab thickness must be a finite number > 0");
  const std::vector<NodeId> order = reachable_nodes(g, root);
  const export_detail::MeshTables meshes = glsl_mesh_tables(g, order);
  bool uses_z = !meshes.empty();  // meshes are solids
  for (NodeId id : order) uses_z |= g.node(id).op == Op::VarZ;
  write_header(out, "Shadertoy fragment shader", opt.glsl.source, order.size());
  out << "// Paste into the Image tab of a new shader on shadertoy.com. Sphere-traces the expression in\n"
         "// the cube [-FREP_RADIUS, FREP_RADIUS]^3 (the surface is where it is zero, negative inside).\n";
  if (!uses_z) out << "// The expression does not use z: it is shown as a slab of thickness 2 * FREP_SLAB.\n";
  write_mesh_note(out, meshes);
  float step = opt.step_scale, p99 = 0;
  std::string why = "  // set by hand";
  if (step == 0) {
    step = auto_step_scale(g, root, opt.radius, &p99);
    char buf[160];
    std::snprintf(buf, sizeof buf, "  // 0.8 / %.3g, the 99th percentile of |grad f| sampled in the cube", static_cast<double>(p99));
    why = step == 1.0f ? "  // |grad f| <= 0.8 at 99% of the samples in the cube" : buf;
  }
  out << "\n#define FREP_RADIUS " << glsl_literal(opt.radius) << "\n#define FREP_STEP_SCALE " << glsl_literal(step) << why
      << "\n#define FREP_MAX_STEPS " << opt.max_steps << "\n";
  if (!uses_z) out << "#define FREP_SLAB " << glsl_literal(opt.slab * opt.radius) << "\n";
  // A 2D shape rocks back and forth; a 3D one turns all the way round.
  out << "#define FREP_AUTO_YAW " << (uses_z ? "(0.3 * iTime)" : "(0.6 * sin(0.3 * iTime))") << "\n\n";
  write_function(out, g, root, opt.glsl, order, meshes);
  out << "\nfloat frep_scene(vec3 p) { return ";
  if (uses_z) out << opt.glsl.function_name << "(p); }\n";
  else out << "max(" << opt.glsl.function_name << "(p), abs(p.z) - FREP_SLAB); }\n";
  out << kMarcher;
}

}  // namespace frep
