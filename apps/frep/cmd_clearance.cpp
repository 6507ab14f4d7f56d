// frep clearance: the gap between two bodies, or how deep they interfere, and where: the minimum
// of S = A + B over space (docs/ugf.md, "Two bodies and clearance"), found by ugf::find_clearance.
// Two meshes are compared as meshes (frep/ugf/mesh_clearance.hpp): the gap between them is their
// exact surface distance; the interval search is left with the interference depth only. This file
// parses the arguments, reports progress and prints what the library found.
#include <fmt/core.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "commands.hpp"
#include "field_output.hpp"
#include "input.hpp"
#include "frep/error.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/copy.hpp"
#include "frep/mesh/mesh_pair.hpp"
#include "frep/ugf/clearance.hpp"
#include "frep/ugf/mesh_clearance.hpp"

namespace frep::cli {
namespace {

std::string fmt_point(const Vec3& p) { return fmt::format("{:.6g}, {:.6g}, {:.6g}", p.x, p.y, p.z); }
// Exact results get all the digits a double needs to round-trip.
std::string fmt_exact(const Vec3& p) { return fmt::format("{:.17g}, {:.17g}, {:.17g}", p.x, p.y, p.z); }

// "triangle 12 (face 5, line 345) of part.obj": a triangle as frep check names it.
std::string triangle_name(const MeshField& f, std::uint32_t t, const std::string& path) {
  const FaceOrigin o = f.welded().origin_of(t);
  std::string s = fmt::format("triangle {}", t);
  if (o.face != t && o.line) s += fmt::format(" (face {}, line {})", o.face, o.line);
  else if (o.face != t) s += fmt::format(" (face {})", o.face);
  else if (o.line) s += fmt::format(" (line {})", o.line);
  return s + " of " + path;
}

struct Args {
  std::string a, b;
  double tolerance = 1e-4;
  std::size_t max_boxes = 20000;
  double time_limit = 0;  // seconds for the interval search, 0 for none
  bool quiet = false;
  bool repair = false;
  FieldOutputOptions region;  // only its bounds: the region searched
};

// The interval search for the minimum of A + B over `box` (`o`: its seeds and Lipschitz bound),
// with progress on stderr for long runs (after the first second: a line rewritten in place about
// every second on a terminal, a new line every 5 s otherwise), unless quiet.
ugf::ClearanceResult search(const Args& a, const Model& ma, NodeId b_root, const Box3& box,
                            ugf::ClearanceOptions o = {}) {
  o.tolerance = static_cast<float>(a.tolerance);
  o.max_boxes = a.max_boxes;
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const double every = tty ? 1.0 : 5.0;
  double next = 1.0;
  bool shown = false;
  if (!a.quiet || a.time_limit > 0)
    o.progress = [&](const ugf::ClearanceProgress& p) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (a.time_limit > 0 && t > a.time_limit) return false;
      if (a.quiet || t < next) return true;
      next = t + every;
      fmt::print(stderr, "{}clearance: {} of at most {} boxes, {:.0f} s; the minimum of A + B is between {:.7g} and {:.7g}{}",
                 tty ? "\r" : "", p.boxes, a.max_boxes, t, p.lower_bound, p.value, tty ? "  " : "\n");
      std::fflush(stderr);
      shown = true;
      return true;
    };
  const ugf::ClearanceResult r =
      ugf::find_clearance(ma.root_expr(), Expr(*ma.graph, b_root), {float(box.lo.x), float(box.hi.x)},
                          {float(box.lo.y), float(box.hi.y)}, {float(box.lo.z), float(box.hi.z)}, o);
  if (shown && tty) fmt::print(stderr, "\n");
  if (!std::isfinite(r.value)) throw InputError(a.a, 0, "A + B is not finite anywhere sampled: no clearance");
  return r;
}

// The interference found by the search: the depth, the deepest point (inside both) and where.
void print_interference(const Args& a, const Tape& ta, const Tape& tb, const ugf::ClearanceResult& r, const char* shallow) {
  fmt::print("interference: depth {:.7g}{}\n", std::max(0.0f, -r.value), -r.value <= a.tolerance ? shallow : "");
  const ugf::DeepestPoint d = ugf::deepest_point(ta, tb, {r.x, r.y, r.z});
  const Vec3f qf(d.point);
  fmt::print("deepest point: {} ({}; {} on {}, {} on {})\n", fmt_point(d.point),
             d.inside_both ? "inside both" : "where A + B is smallest", fmt_point(ugf::project_to_surface(ta, qf)), a.a,
             fmt_point(ugf::project_to_surface(tb, qf)), a.b);
}

// The value is attained at the point printed; the interval bound proves nothing smaller was
// missed by more than the difference. It closes in slowly, since S is constant along the whole
// shortest segment, which boxes cannot separate.
void print_bound(const Args& a, const ugf::ClearanceResult& r) {
  // Within the tolerance (as the search compared it, in float) once it converged; otherwise it
  // ran out of boxes, or was left with boxes too small to split in float.
  const bool close = r.within_tolerance(a.tolerance);
  const char* why = close         ? ""
                    : r.stopped     ? "; the minimum lies between it and the value above (stopped at --time-limit)"
                    : r.boxes >= a.max_boxes
                        ? "; the minimum lies between it and the value above (--max-boxes narrows it)"
                        : "; the minimum lies between it and the value above (boxes that float cannot split remain)";
  fmt::print("proven lower bound of A + B: {:.7g} ({} boxes{})\n", r.lower_bound, r.boxes, why);
}

// Two meshes: the mesh-to-mesh query answers whether they meet or nest, and the exact gap when
// they are apart; only an interference depth needs the interval search.
void mesh_clearance(const Args& a, const Model& ma, NodeId b_root, const Tape& ta, const Tape& tb, const MeshOracle& oa,
                    const Affine3& map_a, const MeshOracle& ob, const Affine3& map_b, const Box3& box_a, const Box3& box_b) {
  const MeshField &fa = oa.field(), &fb = ob.field();
  const MeshPairResult pr = compare_meshes(PlacedMesh::moved_field(fa, map_a), PlacedMesh::moved_field(fb, map_b));
  if (!a.region.bounds.empty() && !a.quiet)
    fmt::print(stderr, "frep clearance: note: --bounds limits only the interference search; two meshes are compared "
                       "over their whole surfaces\n");
  if (pr.apart()) {
    fmt::print("gap: {:.17g}\n", pr.distance);
    fmt::print("nearest points: {} on {}, {} on {}\n", fmt_exact(pr.point_a), a.a, fmt_exact(pr.point_b), a.b);
    fmt::print("exact: the distance between {} and {} (mesh-to-mesh query, {:.3f} s)\n",
               triangle_name(fa, pr.triangle_a, a.a), triangle_name(fb, pr.triangle_b, a.b), pr.seconds);
    return;
  }
  if (pr.surfaces_meet()) {
    const MeshPairContactExample& ex = pr.examples.front();
    const char* kind = ex.kind == PairContact::Cross ? "cross" : ex.kind == PairContact::Overlap ? "overlap" : "touch";
    if (pr.crossing > 0)
      fmt::print("surfaces cross: {} triangle pairs", pr.crossing);
    else
      fmt::print("surfaces touch: {} triangle pairs meet, none crossing", pr.overlapping + pr.touching);
    fmt::print(" (first: {} and {} {} at {})\n", triangle_name(fa, ex.a, a.a), triangle_name(fb, ex.b, a.b), kind,
               fmt_point(ex.point));
  } else {
    const auto nested = [&](std::size_t inside, std::size_t shells, const std::string& inner, const std::string& outer) {
      if (inside == 0) return;
      if (inside == shells) fmt::print("nested: {} lies inside {}", inner, outer);
      else fmt::print("nested: {} of the {} shells of {} lie inside {}", inside, shells, inner, outer);
      fmt::print(" (the surfaces do not meet: {:.9g} apart at {} on {}, {} on {})\n", pr.distance,
                 fmt_point(pr.point_a), a.a, fmt_point(pr.point_b), a.b);
    };
    nested(pr.a_shells_inside_b, pr.a_shells, a.a, a.b);
    nested(pr.b_shells_inside_a, pr.b_shells, a.b, a.a);
  }
  // The shared volume, and the deepest point in it, lie in both bounding boxes; given bounds are
  // box_a (input_region returns them for both).
  const Box3 box = a.region.bounds.empty() ? ugf::shared_region(box_a, box_b) : box_a;
  const ugf::ClearanceResult r =
      search(a, ma, b_root, box, ugf::mesh_interference_options(pr, map_a.is_identity() && map_b.is_identity()));
  if (ugf::only_touching(pr, r, a.tolerance)) {
    // Touching, and no shared volume deeper than the tolerance found.
    const Vec3& p = pr.examples.front().point;
    fmt::print("gap: 0 (the surfaces touch; no interference deeper than --tolerance found)\n");
    fmt::print("nearest points: {} on {}, {} on {}\n", fmt_point(p), a.a, fmt_point(p), a.b);
  } else {
    print_interference(a, ta, tb, r, " (shallower than --tolerance)");
  }
  print_bound(a, r);
}

}  // namespace

void register_clearance(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "clearance",
      "The gap between two bodies (> 0), or how deep they interfere (< 0), and where: the minimum over space of "
      "A + B, their signed distances summed (exact for signed distances such as converted meshes). Two meshes are "
      "compared directly: the gap is their exact mesh-to-mesh distance, and crossing or nested surfaces are named");
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
                  "interval search; needed for unbounded inputs). Two meshes are compared whole: for them it limits "
                  "only the search for the interference depth")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--time-limit", a->time_limit,
                  "Stop the interval search after this many seconds (0: no limit), with the bounds proven by then; "
                  "--max-boxes alone gives the same answer on every machine")
      ->check(finite_non_negative());
  cmd->add_flag("--quiet,-q", a->quiet, "Print only the result (no reading notes, no progress)");
  add_repair_option(cmd, a->repair);
  cmd->callback([a] {
    check_field_output_options(a->region);
    Model ma = load_input(a->a, a->quiet, nullptr, a->repair);
    const Model mb = load_input(a->b, a->quiet, nullptr, a->repair);
    Affine3 map_a, map_b;
    const MeshOracle* oa = as_mesh_oracle(*ma.graph, ma.root, &map_a);
    const MeshOracle* ob = as_mesh_oracle(*mb.graph, mb.root, &map_b);
    const NodeId b_root = copy_expression(*ma.graph, *mb.graph, mb.root);
    const Tape ta = Tape::compile(*ma.graph, ma.root), tb = Tape::compile(*ma.graph, b_root);
    const Box3 box_a = input_region(a->a, ma.info, ta, a->region), box_b = input_region(a->b, mb.info, tb, a->region);
    if (oa && ob) return mesh_clearance(*a, ma, b_root, ta, tb, *oa, map_a, *ob, map_b, box_a, box_b);
    // The shortest segment between two disjoint bodies, and the deepest point of an overlap, lie
    // in the box around both.
    Box3 box = box_a;
    box.add(box_b);
    const ugf::ClearanceResult r = search(*a, ma, b_root, box);
    if (r.value >= 0) {
      const Vec3f p{r.x, r.y, r.z};
      fmt::print("gap: {:.7g}\n", r.value);
      fmt::print("nearest points: {} on {}, {} on {}\n", fmt_point(ugf::project_to_surface(ta, p)), a->a,
                 fmt_point(ugf::project_to_surface(tb, p)), a->b);
    } else {
      print_interference(*a, ta, tb, r, " (within --tolerance: touching)");
    }
    print_bound(*a, r);
  });
}

}  // namespace frep::cli
