#include "frep/slice/slicer.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "frep/contour/bounds.hpp"
#include "frep/error.hpp"
#include "frep/expr/graph.hpp"
#include "frep/slice/cross_section.hpp"
#include "frep/ugf/gyroid.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep::slice {
namespace {

std::string mm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

// The lowest (`up`) or highest z in [a, b] where the plane holds an inside point, to within
// `precision`; NaN if no plane from a to b in steps of `step` does.
double find_extreme(CrossSectioner& sec, double a, double b, double step, double precision, bool up) {
  const double from = up ? a : b, dir = up ? 1 : -1;
  if (sec.has_inside(from)) return from;  // the shape reaches the region's end: cut there
  double outside = from, inside = NAN;
  const int steps = static_cast<int>(std::ceil((b - a) / step));  // slice_field keeps it below 2^22
  for (int k = 1; k <= steps; ++k) {
    const double z = from + dir * std::min(k * step, b - a);
    if (sec.has_inside(z)) {
      inside = z;
      break;
    }
    outside = z;
  }
  if (std::isnan(inside)) return NAN;
  while (std::fabs(inside - outside) > precision) {
    const double mid = 0.5 * (inside + outside);
    if (mid == inside || mid == outside) break;
    (sec.has_inside(mid) ? inside : outside) = mid;
  }
  return 0.5 * (inside + outside);
}

Region translated(Region r, Point2 d) {
  for (Ring& ring : r)
    for (Point2& p : ring) p.x += d.x, p.y += d.y;
  return r;
}

}  // namespace

double gyroid_period(double density, double line_width) {
  FREP_ASSERT(density > 0 && line_width > 0, "gyroid density and line width must be positive");
  return 2.43 * line_width / std::min(density, 1.0);
}

SlicedPart slice_field(const Tape& tape, const FieldInfo& info, const PrintSettings& s, const SlicerOptions& options) {
  check_print_settings(s);
  const double lipschitz = options.lipschitz >= 0 ? options.lipschitz : info.lipschitz;
  auto progress = [&](const char* phase, double f) {
    if (options.progress) options.progress({phase, f});
  };
  // A box holding the inside: the field's own, else an interval search.
  Box3 box = info.bounds;
  if (box.empty()) {
    BoundsSearchOptions bo;
    bo.threads = options.threads;
    bo.lipschitz = lipschitz;
    FieldInfo known = info;
    known.lipschitz = lipschitz;
    box = field_region(tape, known, bo);
  }
  const double h = s.layer_height, cell = s.section_cell;
  CrossSectionOptions co;
  co.cell = cell;
  co.tolerance = s.section_tolerance;
  co.lipschitz = lipschitz;
  co.threads = options.threads;
  // The part's bottom and top, where planes start and stop holding inside points, searched half
  // a layer apart: a region far taller than the printer could take ages (an interval search box,
  // or --bounds, around a flat part).
  const double za = box.lo.z, zb = box.hi.z;
  if (!(zb - za <= 4 * s.max_height + 10 * h) || (zb - za) / (h / 2) > (1 << 22))
    throw InputError("", 0, "the region to slice spans " + mm(zb - za) + " mm in z, far more than the printer's " +
                                mm(s.max_height) + " mm: give --bounds closer to the part");
  double bottom = NAN, top = NAN;
  {
    // The sectioner adds a cell of margin around the region (outside by definition): a shape
    // reaching the region's sides is cut there. This one searches on all threads; the layers
    // below get one per worker.
    CrossSectioner sec(tape, {box.lo.x, box.lo.y}, {box.hi.x, box.hi.y}, co);
    const double precision = 1e-5 * h;
    bottom = find_extreme(sec, za, zb, h / 2, precision, true);
    if (std::isnan(bottom))
      throw InputError("", 0,
                       "nothing to print: no plane through the bounds crosses the inside (the field is not negative "
                       "anywhere, or only in parts thinner than half a layer or a cross-section cell)");
    top = find_extreme(sec, bottom, zb, h / 2, precision, false);
  }
  const double height = std::isnan(top) ? 0 : top - bottom;
  if (height > s.max_height)
    throw InputError("", 0, "the part is " + mm(height) + " mm tall, more than the printer's " + mm(s.max_height) +
                                " mm (max_height)");
  const int count = static_cast<int>(std::llround(height / h));
  if (count < 1)
    throw InputError("", 0, "the part is " + std::to_string(height) + " mm tall, less than half a layer (" +
                                std::to_string(h) + " mm): nothing to print");

  SlicedPart part;
  part.height = height;
  part.z_shift = -bottom;
  std::vector<Region> outlines(static_cast<std::size_t>(count));
  // Layers in parallel, each worker with a cross-sectioner of its own (a layer alone splits
  // into too little work to share, and chaining its rings is serial). The extent of the
  // sections so far: a part wider than the bed stops the slicing at once.
  ThreadPool pool(options.threads);
  std::vector<std::unique_ptr<CrossSectioner>> sections(static_cast<std::size_t>(pool.size()));
  Point2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  std::mutex extent;
  std::atomic<bool> too_big{false};
  std::atomic<int> done{0};
  pool.parallel_for(count, [&](int worker, int i) {
    if (too_big.load()) return;
    auto& own = sections[static_cast<std::size_t>(worker)];
    if (!own) {
      CrossSectionOptions one = co;
      one.threads = 1;
      own = std::make_unique<CrossSectioner>(tape, Point2{box.lo.x, box.lo.y}, Point2{box.hi.x, box.hi.y}, one);
    }
    Region& r = outlines[static_cast<std::size_t>(i)];
    r = own->section(bottom + (i + 0.5) * h);
    Point2 a, b;
    if (bounds(r, a, b)) {
      std::lock_guard<std::mutex> lock(extent);
      lo = {std::min(lo.x, a.x), std::min(lo.y, a.y)};
      hi = {std::max(hi.x, b.x), std::max(hi.y, b.y)};
      if (hi.x - lo.x > s.bed_x || hi.y - lo.y > s.bed_y) too_big = true;
    }
    const int n = ++done;
    if (worker == 0) progress("cross-sections", static_cast<double>(n) / count);
  });
  sections.clear();
  if (too_big)
    throw InputError("", 0, "the part is at least " + mm(hi.x - lo.x) + " x " + mm(hi.y - lo.y) + " mm, bigger than the " +
                                mm(s.bed_x) + " x " + mm(s.bed_y) + " mm bed (bed_x, bed_y)");

  // Placement: centred on the bed, or where the model is.
  if (!(lo.x <= hi.x)) throw InputError("", 0, "every layer's cross-section is empty: nothing to print");
  part.shift = s.keep_position ? Point2{0, 0} : Point2{s.bed_x / 2 - (lo.x + hi.x) / 2, s.bed_y / 2 - (lo.y + hi.y) / 2};
  part.lo = {lo.x + part.shift.x, lo.y + part.shift.y};
  part.hi = {hi.x + part.shift.x, hi.y + part.shift.y};
  if (part.lo.x < 0 || part.lo.y < 0 || part.hi.x > s.bed_x || part.hi.y > s.bed_y)
    throw InputError("", 0, "with --keep-position the part spans x " + mm(part.lo.x) + " .. " + mm(part.hi.x) + ", y " +
                                mm(part.lo.y) + " .. " + mm(part.hi.y) + " mm: off the " + mm(s.bed_x) + " x " +
                                mm(s.bed_y) + " mm bed");
  for (Region& r : outlines) r = translated(std::move(r), part.shift);

  // Gyroid infill: the contours of the gyroid's own field, per worker.
  Graph gyroid_graph;
  std::unique_ptr<Tape> gyroid_tape;
  const double density = s.infill / 100;
  const bool gyroid = s.infill_pattern == InfillPattern::Gyroid && density > 0 && density < 1;
  double period = 0;
  if (gyroid) {
    period = gyroid_period(density, s.line_width);
    const Expr e = ugf::gyroid(gyroid_graph, static_cast<float>(period));
    gyroid_tape = std::make_unique<Tape>(Tape::compile(gyroid_graph, e.id()));
  }

  std::vector<std::unique_ptr<CrossSectioner>> gyroid_sections(static_cast<std::size_t>(pool.size()));
  part.layers.resize(static_cast<std::size_t>(count));
  // Skin is decided on outlines simplified to a hundredth of a line: it needs no more.
  std::vector<Region> rough(outlines.size());
  pool.parallel_for(count, [&](int, int i) {
    rough[static_cast<std::size_t>(i)] = coarse(outlines[static_cast<std::size_t>(i)], 0.01 * s.line_width);
  });
  std::atomic<int> planned{0};
  pool.parallel_for(count, [&](int worker, int i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    std::vector<const Region*> above, below;
    for (int j = 1; j <= s.top_layers; ++j) above.push_back(i + j < count ? &rough[ui + static_cast<std::size_t>(j)] : nullptr);
    for (int j = 1; j <= s.bottom_layers; ++j) below.push_back(i - j >= 0 ? &rough[ui - static_cast<std::size_t>(j)] : nullptr);
    const Region solid = solid_region(rough[ui], above, below);
    InfillSource source;
    std::vector<Polyline> loops;  // this layer's gyroid contours, found once for all its islands
    if (gyroid)
      source = [&, worker](double z, const Region& region) {
        if (!loops.empty()) return clip(loops, region);
        auto& gs = gyroid_sections[static_cast<std::size_t>(worker)];
        if (!gs) {
          CrossSectionOptions go;
          go.cell = period / 48;
          go.tolerance = std::max(s.section_tolerance, period * 1e-4);
          go.corner_cosine = 1;  // the gyroid is smooth
          go.threads = 1;
          gs = std::make_unique<CrossSectioner>(*gyroid_tape, Point2{part.lo.x - 1, part.lo.y - 1},
                                                Point2{part.hi.x + 1, part.hi.y + 1}, go);
        }
        for (Ring& r : gs->section(z)) {
          r.push_back(r.front());
          loops.push_back(std::move(r));
        }
        return clip(loops, region);
      };
    const double section_z = (i + 0.5) * h;
    part.layers[ui] = plan_layer(i, (i + 1) * h, section_z, outlines[ui], solid, s, source, part.lo);
    const int n = ++planned;
    if (worker == 0) progress("tool paths", static_cast<double>(n) / count);
  });
  progress("tool paths", 1);
  for (const Region& r : outlines) part.volume += area(r) * h;
  return part;
}

}  // namespace frep::slice
