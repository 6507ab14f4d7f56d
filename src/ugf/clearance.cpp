// Clearance measurement (clearance.hpp): best-first interval branch and bound on S = A + B, then
// a gradient-descent polish of the best point found. Each box carries the tape simplified to it
// (shared with its parent unless simplifying shrinks it), so that near the bodies only the few
// nearby terms of a converted mesh are evaluated. The caller may seed it with points and watch
// (and stop) it through a progress callback. Then the points that name the result: the nearest
// points of a gap, the deepest point of an interference.
#include "frep/ugf/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <vector>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/ugf/two_body.hpp"

namespace frep::ugf {
namespace {

struct Cell {
  Interval x, y, z;
  float lo;  // proven lower bound of S over the cell
  std::shared_ptr<const Tape> tape;   // S simplified to the cell
  std::shared_ptr<const Tape> point;  // the nearest of it and its ancestors' with register code
  bool operator>(const Cell& o) const { return lo > o.lo; }
};

float mid(Interval i) { return i.lo + 0.5f * (i.hi - i.lo); }

}  // namespace

ClearanceResult find_clearance(Expr A, Expr B, Interval x, Interval y, Interval z, const ClearanceOptions& opt) {
  FREP_ASSERT(x.lo <= x.hi && y.lo <= y.hi && z.lo <= z.hi, "empty region");
  Graph& g = A.graph();
  const auto full = std::make_shared<const Tape>(Tape::compile(g, clearance_field(A, B).id()));
  const Tape& tape = *full;
  IntervalEvaluator iv;
  PointEvaluator pe;
  ClearanceResult res;
  res.value = std::numeric_limits<float>::infinity();

  auto sample = [&](float px, float py, float pz, const Tape& t) {
    const float v = pe.eval(t, px, py, pz);
    if (v < res.value) res.value = v, res.x = px, res.y = py, res.z = pz;
  };
  // The cell's lower bound, and its tape: the parent's, simplified when that shrinks it by a
  // quarter or more (smaller tapes are not worth a copy). Big tapes are kept in SSA form only
  // (interval evaluation needs no registers; point samples use the nearest ancestor's tape that
  // has register code, the whole tape at worst). The open cells' tapes together hold at most kBudget instructions
  // (the big tapes of a converted mesh would otherwise fill memory); beyond it cells share their
  // parent's.
  constexpr std::size_t kBudget = std::size_t{1} << 23, kRegisters = 200000;
  std::size_t held = 0;
  // With a Lipschitz bound L of S: one evaluation of A and B at the cell's centre is both the
  // sample and the bound, S(c) - L r (r: the distance from c to the farthest corner), less what
  // rounding A, B and their sum to float may have cost (2^-22 of |A| + |B|, and the double
  // computation behind them, relative to the point's magnitude).
  const bool lip = opt.lipschitz > 0;
  Tape ta, tb;
  if (lip) ta = Tape::compile(g, A.id()), tb = Tape::compile(g, B.id());
  auto lipschitz_lower = [&](Cell& c) {
    const float cx = mid(c.x), cy = mid(c.y), cz = mid(c.z);
    const float a = pe.eval(ta, cx, cy, cz), b = pe.eval(tb, cx, cy, cz), v = a + b;
    ++res.boxes;
    if (v < res.value) res.value = v, res.x = cx, res.y = cy, res.z = cz;
    const double rx = std::max(double(cx) - c.x.lo, double(c.x.hi) - cx);
    const double ry = std::max(double(cy) - c.y.lo, double(c.y.hi) - cy);
    const double rz = std::max(double(cz) - c.z.lo, double(c.z.hi) - cz);
    const double reach = std::sqrt(rx * rx + ry * ry + rz * rz) * (1 + 1e-12);
    const double slack = 0x1p-22 * (std::fabs(double(a)) + std::fabs(double(b))) +
                         0x1p-40 * opt.lipschitz * std::max({std::fabs(cx), std::fabs(cy), std::fabs(cz), 1.0f});
    const double lo = double(v) - opt.lipschitz * reach - slack;
    float f = static_cast<float>(lo);
    if (double(f) > lo) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    c.lo = std::isnan(lo) ? -std::numeric_limits<float>::infinity() : f;
  };
  auto lower = [&](Cell& c, const std::shared_ptr<const Tape>& parent, const std::shared_ptr<const Tape>& point) {
    if (lip) return lipschitz_lower(c);
    const Interval r = iv.eval(*parent, c.x, c.y, c.z);
    ++res.boxes;
    c.tape = parent;
    c.point = point;
    if (parent->choice_count() > 0 && parent->size() > 32 && held + parent->size() <= kBudget) {
      auto t = std::make_unique<Tape>();
      parent->simplify(iv.values(), iv.choices(), *t, parent->size() <= kRegisters);
      if (4 * t->size() <= 3 * parent->size()) {
        held += t->size();
        c.tape = std::shared_ptr<const Tape>(t.release(), [&held](const Tape* p) {
          held -= p->size();
          delete p;
        });
        if (!c.tape->code().empty()) c.point = c.tape;
      }
    }
    c.lo = r.is_unknown() ? -std::numeric_limits<float>::infinity() : r.lo;
  };

  // A coarse grid first, so that pruning starts with a good upper bound.
  constexpr int kGrid = 8;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j)
      for (int k = 0; k < kGrid; ++k)
        sample(x.lo + (x.hi - x.lo) * (i + 0.5f) / kGrid, y.lo + (y.hi - y.lo) * (j + 0.5f) / kGrid,
               z.lo + (z.hi - z.lo) * (k + 0.5f) / kGrid, tape);

  // The caller's seeds inside the region (outside it, a value would not bound S over the region).
  for (const Vec3f& p : opt.seeds)
    if (x.lo <= p.x && p.x <= x.hi && y.lo <= p.y && p.y <= y.hi && z.lo <= p.z && p.z <= z.hi)
      sample(p.x, p.y, p.z, tape);

  std::priority_queue<Cell, std::vector<Cell>, std::greater<>> open;
  float pruned_lo = std::numeric_limits<float>::infinity();  // smallest bound of discarded cells
  Cell root{x, y, z, 0, nullptr, nullptr};
  lower(root, full, full);
  open.push(root);
  std::size_t reported = 0;  // boxes at the last progress call
  while (!open.empty() && res.boxes < opt.max_boxes) {
    const Cell c = open.top();
    if (c.lo >= res.value - opt.tolerance) {  // every remaining cell is at least this
      res.converged = true;
      break;
    }
    if (opt.progress && res.boxes >= reported + 16) {
      reported = res.boxes;
      if (!opt.progress({res.boxes, res.value, std::min({pruned_lo, c.lo, res.value})})) {
        res.stopped = true;
        break;
      }
    }
    open.pop();
    // Halve the longest side.
    const float wx = c.x.hi - c.x.lo, wy = c.y.hi - c.y.lo, wz = c.z.hi - c.z.lo;
    const int axis = (wx >= wy && wx >= wz) ? 0 : (wy >= wz ? 1 : 2);
    for (int half = 0; half < 2; ++half) {
      Cell d = c;
      Interval& side = axis == 0 ? d.x : axis == 1 ? d.y : d.z;
      const float m = mid(side);
      if (m <= side.lo || m >= side.hi) {  // cannot split further in f32
        pruned_lo = std::min(pruned_lo, c.lo);
        break;
      }
      (half == 0 ? side.hi : side.lo) = m;
      lower(d, c.tape, c.point);
      if (!lip) sample(mid(d.x), mid(d.y), mid(d.z), *d.point);
      if (d.lo < res.value - opt.tolerance) open.push(d);
      else pruned_lo = std::min(pruned_lo, d.lo);
    }
  }

  // Polish: descend along -grad S from the best point, staying in the region.
  GradEvaluator ge;
  float step = 0.01f * std::max({x.hi - x.lo, y.hi - y.lo, z.hi - z.lo});
  for (int it = 0; it < 200 && step > 1e-9f; ++it) {
    const Grad gr = ge.eval(tape, res.x, res.y, res.z);
    const float n = std::sqrt(gr.dx * gr.dx + gr.dy * gr.dy + gr.dz * gr.dz);
    if (!(n > 0) || !std::isfinite(n)) break;
    const float px = std::clamp(res.x - step * gr.dx / n, x.lo, x.hi);
    const float py = std::clamp(res.y - step * gr.dy / n, y.lo, y.hi);
    const float pz = std::clamp(res.z - step * gr.dz / n, z.lo, z.hi);
    const float before = res.value;
    sample(px, py, pz, tape);
    step *= res.value < before ? 1.5f : 0.5f;
  }

  if (open.empty()) res.converged = true;  // every cell was settled
  float lo = pruned_lo;
  if (!open.empty()) lo = std::min(lo, open.top().lo);
  res.lower_bound = std::min(lo, res.value);
  return res;
}

bool ClearanceResult::within_tolerance(double tolerance) const {
  return converged && value - lower_bound <= tolerance * (1 + 1e-6) + 1e-7 * std::fabs(value);
}

Box3 shared_region(const Box3& a, const Box3& b) {
  const Box3 box{max(a.lo, b.lo), min(a.hi, b.hi)};
  return box.inflated(1e-3 * length(box.size()));
}

Vec3 project_to_surface(const Tape& f, const Vec3f& p) {
  GradEvaluator ge;
  const Grad g = ge.eval(f, p.x, p.y, p.z);
  const double n = std::sqrt(double(g.dx) * g.dx + double(g.dy) * g.dy + double(g.dz) * g.dz);
  if (!(n > 0) || !std::isfinite(n)) return Vec3(p);
  const double k = g.v / n;
  return {p.x - k * g.dx, p.y - k * g.dy, p.z - k * g.dz};
}

DeepestPoint deepest_point(const Tape& a, const Tape& b, const Vec3f& p) {
  GradEvaluator ge;
  PointEvaluator pe;
  const auto in_both = [&](const Vec3& q) {
    const float x = float(q.x), y = float(q.y), z = float(q.z);
    return pe.eval(a, x, y, z) < 0 && pe.eval(b, x, y, z) < 0;
  };
  const Grad ga = ge.eval(a, p.x, p.y, p.z);
  const float vb = pe.eval(b, p.x, p.y, p.z);
  const double n = std::sqrt(double(ga.dx) * ga.dx + double(ga.dy) * ga.dy + double(ga.dz) * ga.dz);
  if (n > 0 && std::isfinite(n) && std::isfinite(vb)) {
    const double s = (double(vb) - ga.v) / 2 / n;
    const Vec3 q{p.x + s * ga.dx, p.y + s * ga.dy, p.z + s * ga.dz};
    if (in_both(q)) return {q, true};
  }
  const Vec3 mid = (project_to_surface(a, p) + project_to_surface(b, p)) * 0.5;
  if (in_both(mid)) return {mid, true};
  return {Vec3(p), in_both(Vec3(p))};
}

}  // namespace frep::ugf
