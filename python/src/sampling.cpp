// Field methods that produce data: grids and point samples of signed distances (the calls and
// defaults of `frep sample`, so that both give the same numbers), meshes and pictures.
#include <algorithm>

#include "common.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/render/render2d.hpp"
#include "frep/render/render3d.hpp"
#include "frep/render/shade.hpp"
#include "frep/render/slice.hpp"
#include "frep/sample/grid.hpp"
#include "frep/sample/points.hpp"

namespace frep::python {
namespace {

// The mesh a field is, unmoved (as `frep sample` samples a mesh file or a converted .frep), or null.
const MeshField* mesh_of(const PyField& f) {
  Affine3 map;
  const MeshOracle* mo = as_mesh_oracle(*f.graph, f.field.id(), &map);
  return mo && map.is_identity() ? &mo->field() : nullptr;
}

// `frep sample`'s default region: the cube around a mesh's box, or the box a field carries, 5% of
// its diagonal beyond it; else [-1, 1]^3.
Box3 sample_bounds(const PyField& f, const MeshField* mesh, const std::optional<Box3>& given) {
  if (given) return *given;
  if (mesh) return default_mesh_bounds(mesh->box());
  if (!f.field.info.bounds.empty()) return default_mesh_bounds(f.field.info.bounds);
  return Box3{{-1, -1, -1}, {1, 1, 1}};
}

py::array_t<float> sample_grid_of(const PyField& f, int n, const py::object& bounds, double truncate,
                                  const std::string& method, const std::optional<int>& threads) {
  if (!(truncate >= 0)) throw py::value_error("truncate must be >= 0 (0: off)");
  const MeshField* mesh = mesh_of(f);
  const GridSpec grid = cube_grid(sample_bounds(f, mesh, optional_box(bounds)), n);
  grid.check();
  std::vector<float> data;
  if (mesh) {
    MeshGridOptions go;
    go.threads = threads_of(threads);
    go.truncate = truncate;
    if (method == "cpt") go.method = MeshGridMethod::Cpt;
    else if (method == "queries") go.method = MeshGridMethod::Queries;
    else if (method != "auto") throw py::value_error("method is 'auto', 'cpt' or 'queries', got '" + method + "'");
    py::gil_scoped_release nogil;
    data = sample_grid(*mesh, grid, go);
  } else {
    const Tape tape = f.tape();
    ExprGridOptions eo;
    eo.threads = threads_of(threads);
    eo.truncate = truncate;
    eo.lipschitz = f.field.info.lipschitz;
    py::gil_scoped_release nogil;
    data = sample_grid(tape, grid, eo);
  }
  return own_vector(std::move(data), {n, n, n});
}

py::array_t<float> sample_points_of(const PyField& f, std::size_t count, const std::string& kind,
                                    const std::optional<double>& sigma, const py::object& bounds, std::uint64_t seed,
                                    const std::optional<int>& threads) {
  const bool near = kind == "near-surface" || kind == "near_surface";
  if (!near && kind != "uniform") throw py::value_error("kind is 'uniform' or 'near-surface', got '" + kind + "'");
  if (near && !(sigma && *sigma >= 0 && std::isfinite(*sigma)))
    throw py::value_error("kind='near-surface' needs sigma=, a finite standard deviation >= 0");
  const MeshField* mesh = mesh_of(f);
  const Box3 b = sample_bounds(f, mesh, optional_box(bounds));
  PointSampleOptions po;
  po.seed = seed;
  po.threads = threads_of(threads);
  std::vector<float> data;
  if (mesh) {
    py::gil_scoped_release nogil;
    data = near ? sample_near_surface(*mesh, count, *sigma, po) : sample_uniform(*mesh, b, count, po);
  } else {
    const Tape tape = f.tape();
    py::gil_scoped_release nogil;
    data = near ? sample_near_surface(tape, b, count, *sigma, po) : sample_uniform(tape, b, count, po);
  }
  const auto rows = static_cast<py::ssize_t>(data.size() / 4);
  return own_vector(std::move(data), {rows, 4});
}

py::tuple mesh_of_field(const PyField& f, const std::optional<int>& resolution, const std::optional<double>& cell,
                        const py::object& bounds, const std::string& method, const std::optional<int>& threads,
                        const py::object& max_error) {
  MeshOptions o;
  // "flat", a number (model units) or "Nc" (cells), as `frep mesh --max-error`.
  const std::string error_text = py::str(max_error);
  if (!set_max_error(o, error_text))
    throw py::value_error("max_error is 'flat', a number >= 0 (model units) or 'Nc' (N cells), got '" + error_text + "'");
  if (resolution && cell) throw py::value_error("give resolution= or cell=, not both");
  if (resolution) o.resolution = *resolution;
  if (cell) o.cell_size = *cell;
  if (method == "snap") o.method = MeshMethod::Snap;
  else if (method != "dc") throw py::value_error("method is 'dc' (dual contouring) or 'snap', got '" + method + "'");
  if (auto b = optional_box(bounds)) o.bounds = *b;
  else o.known_bounds = f.field.info.bounds;  // as frep mesh: the box the field carries, else the interval search
  o.lipschitz = f.field.info.lipschitz;
  o.threads = threads_of(threads);
  const Tape tape = f.tape();
  TriMesh mesh;
  {
    py::gil_scoped_release nogil;
    mesh = mesh_expression(tape, o);
  }
  const auto nv = static_cast<py::ssize_t>(mesh.vertices.size()), nt = static_cast<py::ssize_t>(mesh.triangles.size());
  // Vec3 is three doubles and Triangle three uint32: the vectors become the arrays as they are.
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Triangle) == 3 * sizeof(std::uint32_t));
  auto* verts = new std::vector<Vec3>(std::move(mesh.vertices));
  auto* tris = new std::vector<Triangle>(std::move(mesh.triangles));
  py::capsule vfree(verts, [](void* p) { delete static_cast<std::vector<Vec3>*>(p); });
  py::capsule tfree(tris, [](void* p) { delete static_cast<std::vector<Triangle>*>(p); });
  return py::make_tuple(py::array_t<double>({nv, py::ssize_t(3)}, reinterpret_cast<const double*>(verts->data()), vfree),
                        py::array_t<std::uint32_t>({nt, py::ssize_t(3)}, reinterpret_cast<const std::uint32_t*>(tris->data()), tfree));
}

py::array_t<std::uint8_t> image_array(Image&& img) {
  const py::ssize_t h = img.height, w = img.width, c = img.channels;
  return own_vector(std::move(img.pixels), {h, w, c});
}

// `frep render`'s default region for 3D views and slices: the box the field carries grown by
// `margin` of its longest side (a flat side given some depth), else [-1, 1]^3.
Box3 render_bounds(const PyField& f, const std::optional<Box3>& given, double margin) {
  if (given) return *given;
  const Box3& known = f.field.info.bounds;
  if (known.empty()) return Box3{{-1, -1, -1}, {1, 1, 1}};
  const Vec3 size = known.size();
  Box3 box = known.inflated(margin * std::max({size.x, size.y, size.z}));
  for (int i = 0; i < 3; ++i)
    if (!(box.lo[i] < box.hi[i])) box.lo[i] -= 1, box.hi[i] += 1;
  return box;
}

py::array_t<std::uint8_t> render_of(const PyField& f, int size, const std::string& view, const std::string& mode,
                                    const py::object& bounds, bool z_up, double yaw, double pitch, bool ao,
                                    const std::optional<int>& threads) {
  Render3DOptions o;
  o.size = size;
  o.threads = threads_of(threads);
  o.bounds = render_bounds(f, optional_box(bounds), 0.05);
  o.lipschitz = f.field.info.lipschitz;
  o.z_up = z_up;
  o.yaw = yaw;
  o.pitch = pitch;
  if (!parse_view_direction(view, o.view))
    throw py::value_error("view is one of iso, front, back, left, right, top, bottom; got '" + view + "'");
  ShadeOptions so;
  if (mode == "depth") so.mode = ShadeMode::Depth;
  else if (mode == "normals") so.mode = ShadeMode::Normals;
  else if (mode != "shaded") throw py::value_error("mode is 'shaded', 'depth' or 'normals', got '" + mode + "'");
  so.ambient_occlusion = ao;
  so.threads = o.threads;
  if (size < 1 || size > 16384) throw py::value_error("size is 1 to 16384 pixels");
  const Tape tape = f.tape();
  Image img;
  {
    py::gil_scoped_release nogil;
    img = shade(render3d(tape, o), so);
  }
  return image_array(std::move(img));
}

py::array_t<std::uint8_t> slice_of(const PyField& f, const std::string& axis, double offset, int size,
                                   const py::object& bounds, double contour, const std::optional<int>& threads) {
  SliceOptions o;
  if (axis.size() != 1 || axis[0] < 'x' || axis[0] > 'z') throw py::value_error("axis is 'x', 'y' or 'z'");
  o.axis = axis[0] - 'x';
  o.offset = static_cast<float>(offset);
  o.size = size;
  o.threads = threads_of(threads);
  o.bounds = render_bounds(f, optional_box(bounds), 0.2);
  o.contour = contour;
  if (size < 1 || size > 16384) throw py::value_error("size is 1 to 16384 pixels");
  const Tape tape = f.tape();
  Image img;
  {
    py::gil_scoped_release nogil;
    img = render_slice(tape, o);
  }
  return image_array(std::move(img));
}

py::array_t<std::uint8_t> picture_of(const PyField& f, int size, double z, const std::optional<int>& threads) {
  RenderOptions o;
  o.size = size;
  o.z = static_cast<float>(z);
  o.threads = threads_of(threads);
  o.lipschitz = f.field.info.lipschitz;
  if (size < 1 || size > 16384) throw py::value_error("size is 1 to 16384 pixels");
  const Tape tape = f.tape();
  Image img;
  {
    py::gil_scoped_release nogil;
    img = render2d(tape, o);
  }
  return image_array(std::move(img));
}

}  // namespace

void bind_sampling(py::module_& m) {
  auto cls = py::reinterpret_borrow<py::class_<PyField>>(m.attr("Field"));
  cls.def("sample_grid", &sample_grid_of, py::arg("n"), py::arg("bounds") = py::none(), py::arg("truncate") = 0.0,
          py::arg("method") = "auto", py::arg("threads") = py::none(),
          "An n x n x n float32 grid of the field, as `frep sample --grid n` writes it: array[i, j, k] = "
          "f(x_i, y_j, z_k), samples at linspace over the bounds, ends included. bounds: ((x0, y0, z0), (x1, y1, z1)) "
          "(default: the cube around a mesh's box or the box the field carries, 5% of its diagonal beyond, else "
          "[-1, 1]^3). truncate=D > 0: clamp(f, -D, D), computing only what that needs. method (meshes): 'auto', "
          "'cpt' (closest point transform) or 'queries'.")
      .def("sample_points", &sample_points_of, py::arg("n"), py::arg("kind") = "uniform", py::arg("sigma") = py::none(),
           py::arg("bounds") = py::none(), py::arg("seed") = 0, py::arg("threads") = py::none(),
           "n rows (x, y, z, d) of float32, as `frep sample --points n` (kind='uniform': uniform in the bounds) or "
           "`--near-surface n --sigma s` (kind='near-surface': surface points plus Gaussian noise of deviation "
           "sigma) write them; the same seed gives the same rows for any thread count.")
      .def("mesh", &mesh_of_field, py::arg("resolution") = py::none(), py::arg("cell") = py::none(),
           py::arg("bounds") = py::none(), py::arg("method") = "dc", py::arg("threads") = py::none(),
           py::arg("max_error") = "flat",
           "(vertices float64 N x 3, faces uint32 M x 3): a closed, manifold, outward-oriented triangle mesh of where "
           "the field is negative, as `frep mesh` makes it. resolution: cells across the longest side (default 128), "
           "or cell: the cell edge. bounds: the region (default: the box the field carries, else found by interval "
           "search; a shape reaching given bounds is cut and capped there). method: 'dc' (dual contouring) or 'snap'. "
           "max_error: 'flat' merges flat regions only (the surface keeps its points), 0 keeps the uniform mesh of "
           "the grid, a number (model units) or 'Nc' (N cells, e.g. '0.05c') simplifies within that bound.")
      .def("render", &render_of, py::arg("size") = 512, py::arg("view") = "iso", py::arg("mode") = "shaded",
           py::arg("bounds") = py::none(), py::arg("z_up") = false, py::arg("yaw") = 0.0, py::arg("pitch") = 0.0,
           py::arg("ao") = false, py::arg("threads") = py::none(),
           "A shaded 3D view of the surface as `frep render --3d` draws it: uint8 H x W x 3 (H x W x 1 for "
           "mode='depth'), size pixels along the longer side. view: iso, front, back, left, right, top, bottom; mode: "
           "shaded, depth, normals; bounds: the region shown (default: the box the field carries grown by 5%, else "
           "[-1, 1]^3); z_up: z is up (CAD models); yaw, pitch: degrees added to the view's; ao: ambient occlusion.")
      .def("render_slice", &slice_of, py::arg("axis") = "z", py::arg("offset") = 0.0, py::arg("size") = 512,
           py::arg("bounds") = py::none(), py::arg("contour") = 0.0, py::arg("threads") = py::none(),
           "A signed-distance picture of the plane axis = offset (uint8 H x W x 3), as `frep render --slice` draws "
           "it: inside and outside in two colours, contour lines every `contour` units (0: about a tenth of the "
           "picture) and a bold line on f = 0.")
      .def("render_2d", &picture_of, py::arg("size") = 512, py::arg("z") = 0.0, py::arg("threads") = py::none(),
           "The sign of the field on the plane z = const over [-1, 1]^2 (uint8 size x size x 1, 255 where "
           "negative), as `frep render` draws it by default.");
}

}  // namespace frep::python
