// The mesher: options checks, bounds, the grid, the subdivision run over leaves (in parallel,
// per-worker records), and the assembly in leaf order. The steps are declared, one comment
// each, in mesher_steps.hpp.
#include "frep/contour/mesher.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <new>
#include <string>

#include "contour/assemble.hpp"
#include "contour/mesher_steps.hpp"
#include "contour/simplify.hpp"
#include "frep/error.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/util/memory_budget.hpp"
#include "frep/mesh/merge_flat.hpp"

namespace frep {
namespace contour {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

[[noreturn]] void bad_option(const std::string& msg) { throw InputError("", 0, msg); }

}  // namespace

void check_options(const MeshOptions& o) {
  if (o.method != MeshMethod::DualContouring && o.method != MeshMethod::Snap) bad_option("unknown meshing method");
  if (!(o.cell_size >= 0) || !std::isfinite(o.cell_size)) bad_option("the cell size must be a finite number > 0");
  if (o.cell_size == 0 && (o.resolution < 1 || o.resolution > kMaxMeshResolution))
    bad_option("the resolution must be between 1 and " + std::to_string(kMaxMeshResolution) + " cells, got " +
               std::to_string(o.resolution));
  if (!(o.max_error >= 0) || !std::isfinite(o.max_error)) bad_option("the maximum error must be a finite number >= 0");
  if (!o.bounds.empty()) {
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(o.bounds.lo[a]) || !std::isfinite(o.bounds.hi[a])) bad_option("the bounds must be finite");
      if (!(o.bounds.lo[a] < o.bounds.hi[a]))
        bad_option(std::string("the bounds are empty along ") + "xyz"[a] + " (need x0 < x1, y0 < y1, z0 < z1)");
    }
  }
  if (!o.known_bounds.empty())
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(o.known_bounds.lo[a]) || !std::isfinite(o.known_bounds.hi[a]))
        bad_option("the known bounds must be finite");
  if (!(o.edge_tolerance > 0) || !(o.edge_tolerance < 1)) bad_option("the edge tolerance must be in (0, 1)");
  if (o.edge_iterations < 1 || o.edge_iterations > 64) bad_option("edge iterations must be between 1 and 64");
  if (!(o.qef_threshold >= 0) || !(o.qef_threshold <= 1)) bad_option("the QEF threshold must be in [0, 1]");
  if (o.snap.iterations < 0 || o.snap.iterations > 100) bad_option("snap iterations must be between 0 and 100");
  if (!(o.snap.difference_step > 0) || !(o.snap.difference_step <= 0.5))
    bad_option("the central-difference step must be in (0, 0.5] (a fraction of a cell)");
  for (std::size_t i = 0; i < o.tiles.size(); ++i) {
    if (o.tiles[i] < 1) bad_option("tile sizes must be positive");
    if (i > 0 && o.tiles[i - 1] % o.tiles[i] != 0) bad_option("each tile size must be a multiple of the next");
  }
  if (!o.tiles.empty() && o.tiles.back() > 32) bad_option("the leaf tile (the last) must be at most 32 cells");
}

// With a Lipschitz bound, halving is faster (8 children and their 8 centres fill one interval
// pass; boxes settle earlier); without, growing by 4 (64 children in 4 passes).
std::vector<int> default_tiles(int cells, int growth) {
  std::vector<int> t{8};
  while (t.front() * growth < cells) t.insert(t.begin(), t.front() * growth);
  return t;
}

void MeshControl::report(const char* phase, double fraction) {
  if (!o_.progress) return;
  std::lock_guard<std::mutex> lock(mutex_);
  o_.progress(MeshProgress{phase, fraction});
}

MeshRegion find_region(const Tape& tape, const MeshOptions& o, MeshControl& control, MeshStats& st) {
  const auto t0 = Clock::now();
  MeshRegion r{o.bounds, 0, false};
  if (r.box.empty() && !o.known_bounds.empty()) {
    st.bounds_known = true;
    st.found = r.box = o.known_bounds;
    r.margin = 1;
  } else if (r.box.empty()) {
    control.report("bounds", 0);
    BoundsSearchOptions bo = o.bounds_search;
    bo.threads = o.threads;
    bo.lipschitz = o.lipschitz;
    const BoundsResult b = find_bounds(tape, bo);
    st.bounds_found = true;
    st.search_rounds = b.rounds;
    st.seconds_bounds = seconds_since(t0);
    r.margin = 1;
    if (b.empty) {
      r.empty = true;
      return r;
    }
    st.found = r.box = b.box;
  }
  return r;
}

double cell_edge(const Box3& region, const MeshOptions& o) {
  double longest = 0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, region.hi[a] - region.lo[a]);
  const double h = o.cell_size > 0 ? o.cell_size : longest / o.resolution;
  if (!(h > 0) || !std::isfinite(h)) throw InputError("", 0, "the region to mesh has no extent");
  return h;
}

std::uint64_t estimate_surface_cells(const Tape& tape, const MeshOptions& o, const MeshRegion& region, double h) {
  double longest = 0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, region.box.hi[a] - region.box.lo[a]);
  const double cells = longest / h;
  // Past the per-axis limit the grid itself refuses, more precisely than an estimate would.
  if (!(cells > kPilotAbove) || cells > kMaxMeshResolution) return 0;
  MeshOptions pilot = o;
  pilot.resolution = kPilotCells;
  pilot.cell_size = 0;
  pilot.tiles.clear();
  pilot.progress = nullptr;
  // The same region: given bounds as given, a found or known one as known (no second search).
  if (!region.found()) pilot.bounds = region.box;
  else pilot.known_bounds = region.box;
  MeshStats st;
  mesh_expression(tape, pilot, &st);
  const double scale = cells / kPilotCells;
  return static_cast<std::uint64_t>(std::ceil(static_cast<double>(st.surface_cells) * scale * scale));
}

void require_mesh_memory(const Tape& tape, const MeshOptions& o, const MeshRegion& region) {
  const std::uint64_t cells = estimate_surface_cells(tape, o, region, cell_edge(region.box, o));
  if (cells == 0) return;
  require_memory(cells, kBytesPerSurfaceCell, "meshing " + std::to_string(cells) + " cells with surface (estimated from a coarse pass)",
                 "use a lower resolution or a larger cell, or mesh a smaller region with --bounds");
}

// A smaller L for f alone would settle boxes wrongly where the box's distance applies (a region
// wholly inside came out empty).
double cut_lipschitz(double lipschitz) { return lipschitz > 0 ? std::max(lipschitz, 1.0) : lipschitz; }

Box3 cut_box(const MeshGrid& grid, const Box3& region, bool found) {
  // The given bounds are inside the grid, which covers them with whole cells; a found shape is
  // inside the grid's box with a cell to spare.
  Box3 cut = found ? grid.box : region;
  for (int a = 0; a < 3; ++a) {
    cut.lo[a] = std::max(round_f32(cut.lo[a]), grid.box.lo[a]);
    cut.hi[a] = std::min(round_f32(cut.hi[a]), grid.box.hi[a]);
  }
  return cut;
}

std::vector<int> tiles_for(const MeshOptions& o, const MeshGrid& grid, double lipschitz) {
  if (!o.tiles.empty()) return o.tiles;
  return default_tiles(*std::max_element(grid.n.begin(), grid.n.end()), lipschitz > 0 ? 2 : 4);
}

Subdivider& subdivider_for(std::unique_ptr<Subdivider>& sub, const std::vector<int>& tiles, int threads, double lipschitz) {
  if (!sub || sub->options().tiles != tiles || sub->options().lipschitz != lipschitz) {
    SubdivisionOptions so;
    so.tiles = tiles;
    so.threads = threads;
    so.lipschitz = lipschitz;
    sub.reset();  // one pool at a time
    sub = std::make_unique<Subdivider>(so);
  }
  return *sub;
}

std::vector<LeafRecord*> Leaves::in_key_order() const {
  std::vector<LeafRecord*> leaves;
  for (const auto& records : per_worker)
    for (const auto& r : records) leaves.push_back(r.get());
  std::sort(leaves.begin(), leaves.end(), [](const LeafRecord* a, const LeafRecord* b) { return a->key < b->key; });
  return leaves;
}

Leaves build_leaves(Subdivider& sub, const Tape& closed, const MeshGrid& grid, const Box3& cut, const MeshOptions& o,
                    MeshControl& control, bool reporting) {
  const int leaf_size = sub.options().tiles.back();
  const int workers = sub.workers();
  Leaves out;
  out.per_worker.resize(static_cast<std::size_t>(workers));
  std::vector<std::unique_ptr<LeafMesher>> leafers;
  std::vector<std::unique_ptr<LeafRecord>> spare(static_cast<std::size_t>(workers));
  for (int i = 0; i < workers; ++i) {
    leafers.push_back(std::make_unique<LeafMesher>(grid, cut, o));
    spare[static_cast<std::size_t>(i)] = std::make_unique<LeafRecord>();
  }
  const double total = static_cast<double>(grid.n[0]) * grid.n[1] * grid.n[2];
  std::atomic<std::uint64_t> done{0};
  std::atomic<std::int64_t> last_report{0};
  const auto start = Clock::now();

  struct Visitor {
    std::function<void(const IndexBox&)> count;
    std::function<void(int, const Tape&, const IndexBox&)> on_leaf;
    bool settled(int, const IndexBox& b, Interval v) {
      if (v.is_unknown()) return false;
      if (v.hi < 0 || v.lo >= 0) return count(b), true;  // full or empty
      return false;
    }
    void leaf(int wi, const Tape& t, const IndexBox& b) { on_leaf(wi, t, b); }
  };
  Visitor visitor;
  visitor.count = [&](const IndexBox& b) {
    if (o.progress) done.fetch_add(static_cast<std::uint64_t>(b.count()), std::memory_order_relaxed);
  };
  visitor.on_leaf = [&](int wi, const Tape& t, const IndexBox& b) {
    if (control.cancelled()) throw MeshCancelled();
    auto& rec = spare[static_cast<std::size_t>(wi)];
    if (leafers[static_cast<std::size_t>(wi)]->process(t, b, *rec)) {
      rec->key = leaf_key(b.lo, leaf_size);
      out.per_worker[static_cast<std::size_t>(wi)].push_back(std::move(rec));
      rec = std::make_unique<LeafRecord>();
    }
    if (o.progress) {
      const std::uint64_t d = done.fetch_add(static_cast<std::uint64_t>(b.count()), std::memory_order_relaxed) +
                              static_cast<std::uint64_t>(b.count());
      const std::int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start).count();
      std::int64_t last = last_report.load(std::memory_order_relaxed);
      if (reporting && now - last >= 200 && last_report.compare_exchange_strong(last, now))
        control.report("cells", static_cast<double>(d) / total);
    }
  };
  sub.run(closed, grid.grid, visitor);
  if (control.cancelled()) throw MeshCancelled();
  if (reporting) control.report("cells", 1);
  for (const auto& l : leafers) out.zero_corners += l->zero_corners();
  return out;
}

GridPasses::GridPasses(const Tape& tape, const MeshOptions& o, const MeshRegion& region, std::unique_ptr<Subdivider>& sub,
                       MeshControl& control, MeshStats& st)
    : tape_(tape),
      o_(o),
      region_(region),
      sub_(sub),
      control_(control),
      st_(st),
      h_(cell_edge(region.box, o)),
      lipschitz_(cut_lipschitz(o.lipschitz)) {}

PassResult GridPasses::run(double shift) {
  const bool reporting = passes_++ == 0;
  // A shifted grid needs a cell on every side to cover the region.
  const MeshGrid grid = make_grid(region_.box, h_, shift != 0 && region_.margin == 0 ? 1 : region_.margin, shift);
  st_.surface_cells = 0;
  st_.capped = false;
  st_.unresolved = 0;
  st_.bounds = grid.box;
  st_.cells = grid.n;
  st_.cell_size = h_;
  const Box3 cut = cut_box(grid, region_.box, region_.found());
  const Tape closed = close_at_box(tape_, cut);

  const auto t1 = Clock::now();
  const std::vector<int> tiles = tiles_for(o_, grid, lipschitz_);
  Subdivider& sub = subdivider_for(sub_, tiles, o_.threads, lipschitz_);
  const Leaves leaves = build_leaves(sub, closed, grid, cut, o_, control_, reporting);
  st_.seconds_cells += seconds_since(t1);  // over every pass

  const auto t2 = Clock::now();
  const std::vector<LeafRecord*> ordered = leaves.in_key_order();
  PassResult r;
  r.mesh = assemble(ordered, grid, tiles.back(), sub.pool(), &st_.unresolved);
  st_.seconds_assembly += seconds_since(t2);
  st_.leaves = ordered.size();
  for (const LeafRecord* l : ordered) {
    st_.surface_cells += l->cells.size();
    st_.capped |= l->touches_cap;
  }
  st_.vertices = r.mesh.vertices.size();
  st_.triangles = r.mesh.triangles.size();
  r.zero_corners = leaves.zero_corners;
  return r;
}

TriMesh first_mesh(const MeshPass& pass, bool found, MeshStats& st) {
  // -r N makes the longest side exactly N cells: unshifted, a flat extreme face (any CAD part's)
  // would lie on grid corners and cost the second pass below. Given bounds are the user's grid.
  const double first_shift = found ? 1.0 / 64 : 0.0;
  PassResult r = pass(first_shift);
  if (r.zero_corners > 0) {
    // Corners exactly on the surface: faces on grid planes, where "f = 0 is outside" splits
    // touching solids and drops features one cell thick. On a grid moved by a sliver of a cell
    // no corner is on those planes, and dual contouring places the sharp features from the
    // crossings around them.
    st.zero_corners = r.zero_corners;
    st.shifted = true;
    r.mesh = TriMesh{};  // not needed any more: free it for the second pass
    r = pass(first_shift + 1.0 / 64 + (found ? 0.5 : 0.0));
  }
  return std::move(r.mesh);
}

TriMesh retry_while_unresolved(TriMesh mesh, const MeshPass& pass, const std::function<bool()>& cancelled, MeshStats& st) {
  if (st.unresolved == 0) return mesh;
  // Vertices the repairs could not untangle depend on where the surface meets the cells
  // (Fidget's sponge: 24 at 64 cells, none at 63 or 65): another grid of the same cell size,
  // moved by part of a cell, usually has none.
  st.unresolved_first = st.unresolved;
  for (double shift : {0.37, 0.71}) {
    if (cancelled()) throw MeshCancelled();
    const MeshStats best = st;
    // Back to the best mesh's figures, keeping the time of every pass.
    const auto keep_best = [&] {
      const double cells = st.seconds_cells, assembly = st.seconds_assembly;
      st = best;
      st.seconds_cells = cells, st.seconds_assembly = assembly;
    };
    TriMesh other;
    try {
      other = pass(shift).mesh;
    } catch (const MeshCancelled&) {
      throw;
    } catch (const InputError&) {  // the moved grid needs a cell more: beyond floats or the cell limit
      keep_best();
      break;
    } catch (const std::bad_alloc&) {  // no room for a second mesh: keep the first
      keep_best();
      break;
    }
    if (st.unresolved < best.unresolved) {
      st.shifted = true;
      mesh = std::move(other);
    } else {
      keep_best();
    }
    if (st.unresolved == 0) break;
  }
  return mesh;
}

// Merges the finished mesh's flat regions (MeshOptions::merge_flat) and simplifies it
// (MeshOptions::max_error), in place, then validates the result as a solid: both steps keep one
// by construction, but a solid is what frep promises, so a result that fails (never seen) gives
// way to the uniform mesh, said in the stats.
void simplify_output(const Tape& tape, const MeshOptions& o, TriMesh& mesh, MeshControl& control, MeshStats& st) {
  const auto t0 = Clock::now();
  SimplifyOptions so;
  so.cell_size = st.cell_size;
  so.threads = o.threads;
  so.progress = [&](double f) { control.report("simplify", f); };
  so.cancelled = [&] { return control.cancelled(); };
  so.max_error = o.max_error_in_cells ? o.max_error * st.cell_size : o.max_error;
  st.max_error = so.max_error;
  st.triangles_before_simplify = mesh.triangles.size();
  TriMesh simple;
  if (o.merge_flat) {
    MergeFlatReport fr;
    simple = merge_flat_regions(mesh, kFlatTolerance * st.cell_size, &fr);
    st.flat_regions = fr.regions;
  }
  if (so.max_error > 0) {
    simple = simplify_mesh(o.merge_flat ? simple : mesh, tape, so, nullptr);
    ValidationOptions vo;
    vo.threads = o.threads;
    if (validate_mesh(simple, vo).is_solid()) mesh = std::move(simple);
    else st.simplify_rejected = true;
  } else if (st.flat_regions > 0) {
    // Flat regions merged only: merge_flat_regions has checked what it changed (its new
    // triangles against those near them with the validator's exact test, their edges and fans);
    // the rest is the mesher's, so validating the whole mesh would repeat that at the cost of
    // meshing. (Nothing flat: the mesh stays as the mesher made it.)
    mesh = std::move(simple);
  }
  st.vertices = mesh.vertices.size();
  st.triangles = mesh.triangles.size();
  st.seconds_simplify = seconds_since(t0);
}

}  // namespace contour

bool set_max_error(MeshOptions& o, std::string_view text) {
  if (text == "flat") {
    o.max_error = 0, o.max_error_in_cells = true, o.merge_flat = true;
    return true;
  }
  const bool cells = !text.empty() && text.back() == 'c';
  if (cells) text.remove_suffix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v) || !(v >= 0)) return false;
  o.max_error = v, o.max_error_in_cells = cells, o.merge_flat = v > 0;
  return true;
}

struct Mesher::Impl {
  MeshOptions o;
  MeshStats stats;
  std::unique_ptr<Subdivider> sub;
};

Mesher::Mesher(MeshOptions options) : impl_(std::make_unique<Impl>()) {
  contour::check_options(options);
  impl_->o = std::move(options);
}

Mesher::~Mesher() = default;

const MeshStats& Mesher::stats() const { return impl_->stats; }
const MeshOptions& Mesher::options() const { return impl_->o; }

TriMesh Mesher::mesh(const Tape& tape) {
  using namespace contour;
  const MeshOptions& o = impl_->o;
  MeshStats& st = impl_->stats;
  st = MeshStats{};
  FREP_ASSERT(tape.size() > 0, "empty tape");
  MeshControl control(o);
  const MeshRegion region = find_region(tape, o, control, st);
  if (region.empty) return TriMesh{};
  require_mesh_memory(tape, o, region);
  GridPasses passes(tape, o, region, impl_->sub, control, st);
  const MeshPass pass = [&](double shift) { return passes.run(shift); };
  TriMesh mesh = first_mesh(pass, region.found(), st);
  mesh = retry_while_unresolved(std::move(mesh), pass, [&] { return control.cancelled(); }, st);
  // Only a mesh without unresolved vertices is a solid to start from: the checks of every
  // collapse assume one.
  if ((o.max_error > 0 || o.merge_flat) && st.unresolved == 0 && !mesh.triangles.empty()) simplify_output(tape, o, mesh, control, st);
  return mesh;
}

TriMesh mesh_expression(const Tape& tape, const MeshOptions& options, MeshStats* stats) {
  Mesher m(options);
  TriMesh mesh = m.mesh(tape);
  if (stats) *stats = m.stats();
  return mesh;
}

TriMesh mesh_expression(Expr e, const MeshOptions& options, MeshStats* stats) {
  return mesh_expression(Tape::compile(e.graph(), e.id()), options, stats);
}

}  // namespace frep
