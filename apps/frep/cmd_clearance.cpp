// frep clearance: the gap between two bodies, or how deep they interfere, and where: the minimum
// of S = A + B over space (UGF.md, "Two-body field and clearance"), found by ugf::find_clearance.
#include <fmt/core.h>

#include <cmath>
#include <vector>

#include "commands.hpp"
#include "field_output.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/copy.hpp"
#include "frep/ugf/clearance.hpp"

namespace frep::cli {
namespace {

// The point of F's surface nearest p, for a signed distance F: p - F(p) grad F / |grad F|.
Vec3 project(const Tape& t, const Vec3f& p) {
  GradEvaluator ge;
  const Grad g = ge.eval(t, p.x, p.y, p.z);
  const double n = std::sqrt(double(g.dx) * g.dx + double(g.dy) * g.dy + double(g.dz) * g.dz);
  if (!(n > 0) || !std::isfinite(n)) return Vec3(p);
  const double k = g.v / n;
  return {p.x - k * g.dx, p.y - k * g.dy, p.z - k * g.dz};
}

// A point inside both bodies from the minimizer p of A + B. That sum is constant along the whole
// deepest segment, so p may lie anywhere on it, even outside one body: moving along A's gradient
// by (B - A) / 2 evens the two depths (exact for signed distances). Falls back on the middle of
// the two surface points; `inside` says whether the point found is inside both.
Vec3 deepest_point(const Tape& ta, const Tape& tb, const Vec3f& p, bool& inside) {
  GradEvaluator ge;
  PointEvaluator pe;
  const auto in_both = [&](const Vec3& q) {
    const float x = float(q.x), y = float(q.y), z = float(q.z);
    return pe.eval(ta, x, y, z) < 0 && pe.eval(tb, x, y, z) < 0;
  };
  inside = true;
  const Grad ga = ge.eval(ta, p.x, p.y, p.z);
  const float vb = pe.eval(tb, p.x, p.y, p.z);
  const double n = std::sqrt(double(ga.dx) * ga.dx + double(ga.dy) * ga.dy + double(ga.dz) * ga.dz);
  if (n > 0 && std::isfinite(n) && std::isfinite(vb)) {
    const double s = (double(vb) - ga.v) / 2 / n;
    const Vec3 q{p.x + s * ga.dx, p.y + s * ga.dy, p.z + s * ga.dz};
    if (in_both(q)) return q;
  }
  const Vec3 mid = (project(ta, p) + project(tb, p)) * 0.5;
  if (in_both(mid)) return mid;
  inside = in_both(Vec3(p));
  return Vec3(p);
}

std::string fmt_point(const Vec3& p) { return fmt::format("{:.6g}, {:.6g}, {:.6g}", p.x, p.y, p.z); }

}  // namespace

void register_clearance(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "clearance",
      "The gap between two bodies (> 0), or how deep they interfere (< 0), and where: the minimum over space of "
      "A + B, their signed distances summed (exact for signed distances such as converted meshes)");
  struct Args {
    std::string a, b;
    double tolerance = 1e-4;
    std::size_t max_boxes = 20000;
    FieldOutputOptions region;  // only its bounds: the region searched
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("A", a->a, kFieldInputHelp)->required();
  cmd->add_option("B", a->b, "The second body, the same kinds of file as A")->required();
  cmd->add_option("--tolerance", a->tolerance,
                  "Stop once the value found is within this of the proven lower bound (absolute, in the inputs' units)")
      ->check(finite_number(true))
      ->capture_default_str();
  cmd->add_option("--max-boxes", a->max_boxes, "Most boxes the interval search examines")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 32))
      ->capture_default_str();
  cmd->add_option("--bounds", a->region.bounds,
                  "Region searched, x0,y0,z0,x1,y1,z1 (default: the box around both inputs, their own or found by "
                  "interval search; needed for unbounded inputs)")
      ->delimiter(',')
      ->expected(6);
  cmd->callback([a] {
    check_field_output_options(a->region);
    Model ma = load_input(a->a);
    const Model mb = load_input(a->b);
    const NodeId b_root = copy_expression(*ma.graph, *mb.graph, mb.root);
    const Tape ta = Tape::compile(*ma.graph, ma.root), tb = Tape::compile(*ma.graph, b_root);
    // The shortest segment between two disjoint bodies, and the deepest point of an overlap, lie
    // in the box around both.
    Box3 box = input_region(a->a, ma.info, ta, a->region);
    box.add(input_region(a->b, mb.info, tb, a->region));
    ugf::ClearanceOptions o;
    o.tolerance = static_cast<float>(a->tolerance);
    o.max_boxes = a->max_boxes;
    const ugf::ClearanceResult r =
        ugf::find_clearance(ma.root_expr(), Expr(*ma.graph, b_root), {float(box.lo.x), float(box.hi.x)},
                            {float(box.lo.y), float(box.hi.y)}, {float(box.lo.z), float(box.hi.z)}, o);
    if (!std::isfinite(r.value)) throw InputError(a->a, 0, "A + B is not finite anywhere sampled: no clearance");
    const Vec3f p{r.x, r.y, r.z};
    if (r.value >= 0) {
      fmt::print("gap: {:.7g}\n", r.value);
      fmt::print("nearest points: {} on {}, {} on {}\n", fmt_point(project(ta, p)), a->a, fmt_point(project(tb, p)), a->b);
    } else {
      fmt::print("interference: depth {:.7g}{}\n", -r.value,
                 -r.value <= a->tolerance ? " (within --tolerance: touching)" : "");
      bool inside = false;
      const Vec3 q = deepest_point(ta, tb, p, inside);
      const Vec3f qf(q);
      fmt::print("deepest point: {} ({}; {} on {}, {} on {})\n", fmt_point(q),
                 inside ? "inside both" : "where A + B is smallest", fmt_point(project(ta, qf)), a->a,
                 fmt_point(project(tb, qf)), a->b);
    }
    // The value is attained at the point printed; the interval bound proves nothing smaller was
    // missed by more than the difference. It closes in slowly, since S is constant along the
    // whole shortest segment, which boxes cannot separate.
    const bool converged = r.value - r.lower_bound <= a->tolerance;
    fmt::print("proven lower bound of A + B: {:.7g} ({} boxes{})\n", r.lower_bound, r.boxes,
               converged ? "" : "; the minimum lies between it and the value above (--max-boxes narrows it)");
  });
}

}  // namespace frep::cli
