// frep sample: dense grids (optionally truncated at +-D) and point samples of exact signed
// distances, from a mesh or an expression, written as float32 .npy files (layout in
// frep/sample/grid.hpp, docs/sampling.md); meshes optionally normalized first, and a one-line
// JSON summary for scripts such as frep dataset.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "commands.hpp"
#include "input.hpp"
#include "frep/util/memory_budget.hpp"
#include "frep/error.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/script/load.hpp"
#include "frep/io/npy.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/sample/grid.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/sample/points.hpp"

namespace frep::cli {
namespace {

Box3 parse_bounds(const std::vector<double>& v) {
  if (v.size() != 6) throw CLI::ValidationError("--bounds", "needs six numbers x0,y0,z0,x1,y1,z1");
  const Box3 b{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !(b.lo[a] < b.hi[a]))
      throw CLI::ValidationError("--bounds", "needs finite numbers with x0 < x1, y0 < y1, z0 < z1");
  // Samples are float32 points: bounds beyond float range would give infinite coordinates.
  for (double c : v)
    if (!(std::fabs(c) <= FLT_MAX))
      throw CLI::ValidationError("--bounds", fmt::format("{:g} is beyond the range of 32-bit floats (+-3.4e38), "
                                                         "which samples are written in", c));
  return b;
}

// Writes no inf or NaN into a file meant for training: the first sample that is not finite
// refuses the whole run, naming its point and the option that put it there. A distance is
// finite wherever it fits a float (converted expressions included: frep convert's stay finite
// far from the part); beyond, or where an expression of the user's divides by zero, it is not.
void refuse_non_finite(const std::vector<float>& data, const std::optional<GridSpec>& grid, std::size_t uniform_rows,
                       const std::string& input, bool mesh) {
  std::size_t bad = 0, first = 0;
  const std::size_t n = grid ? data.size() : data.size() / 4;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[grid ? i : 4 * i + 3]) && bad++ == 0) first = i;
  if (bad == 0) return;
  Vec3 p;
  const char* option = "--bounds";
  if (grid) {
    const std::size_t nz = static_cast<std::size_t>(grid->counts[2]), ny = static_cast<std::size_t>(grid->counts[1]);
    p = {grid->coord(0, static_cast<int>(first / (ny * nz))), grid->coord(1, static_cast<int>(first / nz % ny)),
         grid->coord(2, static_cast<int>(first % nz))};
  } else {
    p = {data[4 * first], data[4 * first + 1], data[4 * first + 2]};
    if (first >= uniform_rows) option = "--sigma";
  }
  const float v = data[grid ? first : 4 * first + 3];
  throw InputError(
      input, 0,
      fmt::format("the {} is {} at ({:g}, {:g}, {:g}) ({} of {} samples), and frep sample writes only finite values: "
                  "give {} {}{}",
                  mesh ? "distance" : "field", v, p.x, p.y, p.z, bad, n, std::isnan(v) ? "other" : "a smaller", option,
                  mesh ? " (a distance beyond 3.4e38 does not fit a 32-bit float)"
                  : std::isnan(v)
                      ? ""
                      : " (a distance beyond 3.4e38 does not fit a 32-bit float; expressions converted by an earlier "
                        "frep overflow about 2e19 from their part: convert them again)"));
}

// --normalize: the similarity p -> (p - offset) * scale applied to the mesh's vertices before
// sampling, so that original = normalized / scale + offset and distances scale by `scale`.
struct Normalization {
  std::string mode = "none";
  double scale = 1;
  Vec3 offset{0, 0, 0};
};

// unit-cube: the box of the used vertices centred at the origin, its longest side 1.
// unit-sphere: the same centre, the farthest used vertex at distance 1.
Normalization normalize_mesh(TriMesh& mesh, const std::string& mode) {
  Normalization n;
  n.mode = mode;
  if (mode == "none" || mesh.triangles.empty()) return n;  // no triangles: MeshField says so
  const Box3 box = bounding_box(mesh);
  n.offset = box.center();
  double extent = 0;
  if (mode == "unit-cube") {
    const Vec3 s = box.size();
    extent = std::max({s.x, s.y, s.z});
  } else {
    for (const Triangle& t : mesh.triangles)
      for (std::uint32_t v : t) extent = std::max(extent, length(mesh.vertices[v] - n.offset));
  }
  if (!(extent > 0) || !std::isfinite(extent))
    throw InputError(mesh.name, 0, fmt::format("cannot normalize to a {}: the mesh's box has no extent", mode));
  n.scale = 1 / extent;
  for (Vec3& v : mesh.vertices) v = (v - n.offset) * n.scale;
  return n;
}

// A JSON string (quotes, backslashes and control characters escaped).
std::string json_str(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += c;
    else if (static_cast<unsigned char>(c) < 0x20) o += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
    else o += c;
  }
  return o + "\"";
}

// The shortest number that reads back to the same double, or null (JSON has no infinities).
std::string json_num(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("null"); }

}  // namespace

void register_sample(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sample",
      "Sample exact signed distances (negative inside) of a mesh or an expression into a float32 .npy file: "
      "a dense grid (--grid; --truncate D for the truncated signed distance) or points with their distances "
      "(--points, --near-surface), as used to train neural SDFs");
  struct Args {
    std::string input, output, sign = "pseudonormal", method = "auto";
    int grid = 0;
    std::vector<double> bounds;
    std::size_t points = 0, near = 0;
    std::optional<double> sigma, truncate;
    std::uint64_t seed = 0;
    double weld_tolerance = 0;
    int threads = 0;
    std::string normalize = "none";
    bool quiet = false, repair = false, json = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("INPUT", a->input, "Mesh (.stl, .obj, .ply, .off) or expression (.vm, .rhai, .frep)")->required();
  cmd->add_option("-o,--output", a->output, "Output .npy file")->required();
  auto* grid = cmd->add_option("--grid", a->grid,
                               "Dense N x N x N grid: array[i][j][k] = f(x_i, y_j, z_k), samples at linspace over the "
                               "bounds, ends included")
                   ->check(CLI::Range(2, 4096));
  cmd->add_option("--bounds", a->bounds,
                  "x0,y0,z0,x1,y1,z1 (default: the cube around a mesh's box, 5% of its diagonal beyond it; the same "
                  "around the box an expression file carries, as frep convert writes it; else [-1,1]^3)")
      ->delimiter(',')
      ->expected(6);
  // Unsigned options would take "-1" as 2^64 - 1: whole numbers >= 0 only.
  auto* points = cmd->add_option("--points", a->points, "P points uniform in the bounds: rows (x, y, z, d)")
                     ->check(whole_non_negative());
  auto* near = cmd->add_option("--near-surface", a->near,
                               "K points near the surface: surface samples plus Gaussian noise of deviation --sigma")
                   ->check(whole_non_negative());
  auto* sigma = cmd->add_option("--sigma", a->sigma, "Standard deviation of the noise of --near-surface (length)")
                    ->check(finite_non_negative());
  near->needs(sigma);
  sigma->needs(near);
  grid->excludes(points)->excludes(near);
  auto* truncate =
      cmd->add_option("--truncate", a->truncate,
                      "With --grid: the truncated signed distance clamp(d, -D, D) for a length D > 0, exact within D of "
                      "the surface and +-D beyond, computing only what that needs (meshes that are not valid solids: "
                      "every sample queried, then clamped)")
          ->type_name("D")
          ->check(finite_number(true));
  truncate->needs(grid)->excludes(points)->excludes(near);
  cmd->add_option("--seed", a->seed, "Seed of the random points (default 0); the same seed gives the same file")
      ->check(whole_non_negative());
  cmd->add_option("--sign", a->sign,
                  "Meshes: sign of valid solids by the closest feature's 'pseudonormal' (default; exact, and the fast "
                  "grid algorithm) or the 'winding' number; other meshes always use the winding number")
      ->check(CLI::IsMember({"pseudonormal", "winding"}));
  cmd->add_option("--method", a->method,
                  "Meshes, --grid: 'auto' (default), 'cpt' (closest point transform) or 'queries' (one oracle query per "
                  "sample)")
      ->check(CLI::IsMember({"auto", "cpt", "queries"}));
  cmd->add_option("--weld-tolerance", a->weld_tolerance, "Meshes: merge vertices closer than this first (default 0)")
      ->check(finite_non_negative());
  cmd->add_option("--threads", a->threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 1024));
  cmd->add_option("--normalize", a->normalize,
                  "Meshes: 'unit-cube' (the box of the mesh centred at the origin, its longest side 1; default "
                  "bounds [-0.55,0.55]^3), 'unit-sphere' (the box's centre at the origin, the farthest vertex at "
                  "distance 1; default bounds [-1.1,1.1]^3) or 'none' (default). Coordinates, distances, --sigma "
                  "and --truncate are then in normalized units: original = normalized / scale + offset")
      ->check(CLI::IsMember({"none", "unit-cube", "unit-sphere"}));
  cmd->add_flag("--json", a->json,
                "Print a one-line JSON summary instead of the text one (output, shape, count, triangles, check "
                "verdict, repair, normalization, bounds, seconds)");
  cmd->add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
  add_repair_option(cmd, a->repair);
  cmd->callback([a] {
    if (a->grid == 0 && a->points == 0 && a->near == 0)
      throw CLI::ValidationError("frep sample", "give --grid N, --points P or --near-surface K --sigma S");
    std::optional<Box3> bounds;
    if (!a->bounds.empty()) bounds = parse_bounds(a->bounds);
    const std::filesystem::path out(a->output);
    if (out.extension() != ".npy" && !is_device(a->output))
      throw CLI::ValidationError("--output", "frep sample writes NumPy .npy files: name the output X.npy (got " +
                                                 a->output + ")");
    check_output(a->output, {a->input});
    const auto t0 = std::chrono::steady_clock::now();
    // Both kinds of points are held at once, with a copy: refuse what cannot fit before starting
    // (a sum that wraps would pass).
    const std::uint64_t total_points = a->points > UINT64_MAX - a->near ? UINT64_MAX : a->points + a->near;
    const std::size_t work = a->grid ? std::size_t(a->grid) * a->grid * a->grid : total_points;
    const bool show = !a->quiet && work >= (std::size_t(1) << 21);
    int last = -1;
    auto progress = [show, &last](const char* stage, double f) {
      const int pct = static_cast<int>(100 * f);
      if (!show || pct / 10 == last / 10) return;
      last = pct;
      std::fprintf(stderr, "frep sample: %3d%% %s\n", pct, stage);
    };
    std::vector<float> data;
    std::vector<std::size_t> shape;
    std::string what, repair_summary_text;
    std::size_t triangles = 0;
    Normalization norm;
    Box3 used;  // the bounds sampled, printed so that another run can reuse them
    bool from_mesh = false;
    std::optional<bool> solid;
    std::string check;
    try {
      if (!a->grid)
        require_memory(total_points, 32, "sampling " + std::to_string(total_points) + " points", "sample fewer points");
      // A mesh, or an expression file that is one mesh leaf (a .frep frep convert wrote): sampled
      // from the mesh itself (the closest point transform for grids).
      std::optional<MeshField> own;
      std::optional<Model> model;
      const MeshField* mesh_field = nullptr;
      if (a->normalize != "none" && format_from_extension(a->input) == MeshFormat::Unknown)
        throw CLI::ValidationError("--normalize", "applies to meshes (.stl, .obj, .ply, .off) only");
      if (format_from_extension(a->input) != MeshFormat::Unknown) {
        MeshFieldOptions fo;
        fo.sign = a->sign == "winding" ? SignMethod::WindingNumber : SignMethod::Pseudonormal;
        fo.weld_tolerance = a->weld_tolerance;
        fo.threads = a->threads;
        TriMesh mesh = read_mesh_noting(a->input);
        triangles = mesh.num_triangles();
        mesh = repaired_if_asked(std::move(mesh), a->repair, a->quiet, &repair_summary_text);
        norm = normalize_mesh(mesh, a->normalize);
        own.emplace(mesh, fo);
        mesh_field = &*own;
        if (!own->solid() && !a->quiet)
          std::fprintf(stderr, "frep sample: %s: %s; signs from the winding number\n", a->input.c_str(),
                       own->summary().c_str());
      } else {
        model.emplace(load_input(a->input, a->quiet, nullptr, a->repair));
        Affine3 map;
        const MeshOracle* mo = as_mesh_oracle(*model->graph, model->root, &map);
        if (mo && map.is_identity()) mesh_field = &mo->field();
      }
      if (mesh_field) {
        from_mesh = true;
        const MeshField& field = *mesh_field;
        // Normalized meshes share fixed bounds, so that grids of a data set line up voxel for voxel.
        const double half = a->normalize == "unit-cube" ? 0.55 : 1.1;
        const Box3 b = bounds                      ? *bounds
                       : a->normalize == "none" ? default_mesh_bounds(field.box())
                                                : Box3{{-half, -half, -half}, {half, half, half}};
        used = b;
        solid = field.solid();
        check = field.summary();
        if (a->grid) {
          MeshGridOptions go;
          go.threads = a->threads;
          go.method = a->method == "cpt" ? MeshGridMethod::Cpt
                                          : (a->method == "queries" ? MeshGridMethod::Queries : MeshGridMethod::Auto);
          go.progress = progress;
          go.truncate = a->truncate.value_or(0);
          MeshGridStats st;
          data = sample_grid(field, cube_grid(b, a->grid), go, &st);
          what = st.method == MeshGridMethod::Cpt
                     ? fmt::format("closest point transform, {} polyhedra, {:.2f} distances per sample", st.features,
                                   static_cast<double>(st.evaluations) / static_cast<double>(data.size()))
                     : "one oracle query per sample";
          if (a->truncate)
            what += st.method == MeshGridMethod::Cpt
                        ? fmt::format(", truncated at +-{:g}: {} samples exact, the rest +-{:g}", *a->truncate,
                                      st.band_samples, *a->truncate)
                        : fmt::format(", truncated at +-{:g} (clamped)", *a->truncate);
        } else {
          PointSampleOptions po;
          po.seed = a->seed;
          po.threads = a->threads;
          data = sample_uniform(field, b, a->points, po);
          if (a->near) {
            const std::vector<float> n = sample_near_surface(field, a->near, *a->sigma, po);
            data.insert(data.end(), n.begin(), n.end());
          }
        }
        what += std::string(what.empty() ? "" : ", ") +
                (field.sign() == SignMethod::Pseudonormal ? "pseudonormal signs" : "winding-number signs");
      } else {
        const Model& m = *model;
        const Tape tape = Tape::compile(*m.graph, m.root);
        // The file's box of its inside (frep convert writes the mesh's), as for a mesh; else
        // Fidget's usual region.
        const bool known = !m.info.bounds.empty();
        if (!bounds && !known && !a->quiet)
          std::fprintf(stderr, "frep sample: no --bounds given: sampling the expression over [-1,1]^3\n");
        const Box3 b = bounds ? *bounds : known ? default_mesh_bounds(m.info.bounds) : Box3{{-1, -1, -1}, {1, 1, 1}};
        used = b;
        if (a->grid) {
          ExprGridOptions eo;
          eo.threads = a->threads;
          eo.truncate = a->truncate.value_or(0);
          eo.lipschitz = m.info.lipschitz;
          data = sample_grid(tape, cube_grid(b, a->grid), eo);
          what = "pruned evaluator";
          if (a->truncate) what += fmt::format(", truncated at +-{:g}", *a->truncate);
        } else {
          PointSampleOptions po;
          po.seed = a->seed;
          po.threads = a->threads;
          data = sample_uniform(tape, b, a->points, po);
          if (a->near) {
            const std::vector<float> n = sample_near_surface(tape, b, a->near, *a->sigma, po);
            data.insert(data.end(), n.begin(), n.end());
          }
        }
      }
    } catch (const InputError& e) {
      // The sampler sees a mesh or a tape, not a file: name the input here.
      if (!e.file().empty()) throw;
      throw InputError(a->input, e.line(), e.detail(), e.byte_offset());
    }
    refuse_non_finite(data, a->grid ? std::optional<GridSpec>(cube_grid(used, a->grid)) : std::nullopt, a->points,
                      a->input, from_mesh);
    if (a->grid) shape = {std::size_t(a->grid), std::size_t(a->grid), std::size_t(a->grid)};
    else shape = {data.size() / 4, 4};
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_npy(a->output, data.data(), shape);
    if (a->json) {
      // One line, for scripts (frep dataset reads it): null where a field does not apply.
      fmt::print("{{\"input\": {}, \"output\": {}, \"shape\": [{}], \"count\": {}, \"triangles\": {}, "
                 "\"solid\": {}, \"check\": {}, \"repair\": {}, \"normalize\": {}, \"scale\": {}, "
                 "\"offset\": [{}, {}, {}], \"bounds\": [{}, {}, {}, {}, {}, {}], \"seconds\": {}}}\n",
                 json_str(a->input), json_str(a->output), fmt::join(shape, ", "), a->grid ? data.size() : data.size() / 4,
                 from_mesh && triangles ? std::to_string(triangles) : "null",
                 solid ? (*solid ? "true" : "false") : "null", solid ? json_str(check) : "null",
                 a->repair ? json_str(repair_summary_text) : "null", json_str(norm.mode), json_num(norm.scale),
                 json_num(norm.offset.x), json_num(norm.offset.y), json_num(norm.offset.z), json_num(used.lo.x),
                 json_num(used.lo.y), json_num(used.lo.z), json_num(used.hi.x), json_num(used.hi.y),
                 json_num(used.hi.z), json_num(secs));
      std::fflush(stdout);
      return;
    }
    if (a->quiet) return;
    std::string dims;
    for (std::size_t s : shape) dims += (dims.empty() ? "" : " x ") + std::to_string(s);
    fmt::print("wrote {}: float32 {} ({}), {:.2f} s\n  bounds {},{},{},{},{},{}\n", a->output, dims,
               what.empty() ? "points" : what, secs, used.lo.x, used.lo.y, used.lo.z, used.hi.x, used.hi.y, used.hi.z);
  });
}

}  // namespace frep::cli
