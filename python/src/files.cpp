// Files: loading fields (meshes, expressions, scripts), checking, repairing and converting meshes,
// and meshes as NumPy arrays. The reports come as dicts from the library's own JSON.
#include <chrono>
#include <filesystem>

#include "common.hpp"
#include "frep/convert/convert.hpp"
#include "frep/convert/make_solid.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/repair.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/script/load.hpp"
#include "frep/script/rhai.hpp"
#include "frep/script/save.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep::python {
namespace {

py::object json_dict(const std::string& json) { return py::module_::import("json").attr("loads")(utf8(json)); }

// A mesh from (vertices N x 3, faces M x 3) arrays.
TriMesh mesh_of_arrays(const py::array& vertices, const py::array& faces, const std::string& name) {
  const auto v = py::array_t<double, py::array::forcecast>(vertices);
  const auto f = py::array_t<std::int64_t, py::array::forcecast>(faces);
  if (v.ndim() != 2 || v.shape(1) != 3) throw py::value_error("vertices must be an N x 3 array");
  if (f.ndim() != 2 || f.shape(1) != 3) throw py::value_error("faces must be an M x 3 array of vertex indices");
  TriMesh mesh;
  mesh.name = name;
  const auto vr = v.unchecked<2>();
  const auto fr = f.unchecked<2>();
  mesh.vertices.reserve(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) mesh.vertices.push_back({vr(i, 0), vr(i, 1), vr(i, 2)});
  mesh.triangles.reserve(static_cast<std::size_t>(f.shape(0)));
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    for (int k = 0; k < 3; ++k)
      if (fr(i, k) < 0 || fr(i, k) >= v.shape(0))
        throw py::value_error("face " + std::to_string(i) + " refers to vertex " + std::to_string(fr(i, k)) +
                              ", which does not exist");
    mesh.add_triangle(static_cast<std::uint32_t>(fr(i, 0)), static_cast<std::uint32_t>(fr(i, 1)),
                      static_cast<std::uint32_t>(fr(i, 2)));
  }
  return mesh;
}

// A path (read as frep reads it) or a (vertices, faces) pair.
TriMesh mesh_of(const py::object& mesh) {
  if (py::isinstance<py::str>(mesh) || py::isinstance(mesh, py::module_::import("os").attr("PathLike"))) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(mesh));
    py::gil_scoped_release nogil;
    return read_mesh(path);
  }
  const auto pair = py::cast<std::pair<py::array, py::array>>(mesh);
  return mesh_of_arrays(pair.first, pair.second, "");
}

std::string path_of(const py::object& p) { return py::str(py::module_::import("os").attr("fspath")(p)); }

py::tuple mesh_arrays(TriMesh&& mesh) {
  std::vector<double> v;
  v.reserve(3 * mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) v.insert(v.end(), {p.x, p.y, p.z});
  std::vector<std::uint32_t> t;
  t.reserve(3 * mesh.triangles.size());
  for (const Triangle& tr : mesh.triangles) t.insert(t.end(), tr.begin(), tr.end());
  const auto nv = static_cast<py::ssize_t>(mesh.vertices.size()), nt = static_cast<py::ssize_t>(mesh.triangles.size());
  return py::make_tuple(own_vector(std::move(v), {nv, 3}), own_vector(std::move(t), {nt, 3}));
}

}  // namespace

void bind_files(py::module_& m) {
  m.def("load", [](const py::object& path, bool repair, double weld_tolerance, const std::optional<int>& threads) {
    ConvertOptions o;
    o.repair = repair;
    o.weld_tolerance = weld_tolerance;
    o.threads = threads_of(threads);
    const std::string p = path_of(path);
    Model model;
    {
      py::gil_scoped_release nogil;
      model = load_field(p, o);
    }
    return PyField::from_model(std::move(model));
  }, py::arg("path"), py::arg("repair") = false, py::arg("weld_tolerance") = 0.0, py::arg("threads") = py::none(),
        "A field from a file: an expression (.vm, .rhai, .frep) or a mesh (.stl, .obj, .ply, .off), whose field is "
        "its exact signed distance (checked as frep check does; repair=True repairs a mesh that is not a valid solid "
        "first, as --repair). Raises frep.InputError naming the file and line.");
  m.def("parse", [](const std::string& text, const std::string& name) {
    return PyField::from_model(parse_rhai(text, name));
  }, py::arg("text"), py::arg("name") = "<string>",
        "A field from a Rhai script's text (Fidget's language, docs/rhai.md); name appears in errors.");

  m.def("check", [](const py::object& mesh, double weld_tolerance, bool self_intersections, std::size_t examples,
                    const std::optional<int>& threads) {
    const TriMesh tm = mesh_of(mesh);
    ValidationOptions o;
    o.weld_tolerance = weld_tolerance;
    o.self_intersections = self_intersections;
    o.max_examples = examples;
    o.threads = threads_of(threads);
    ValidationReport r;
    {
      py::gil_scoped_release nogil;
      r = validate_mesh(tm, o);
    }
    py::dict d = json_dict(r.to_json());
    d["is_solid"] = r.is_solid();
    d["summary"] = utf8(r.summary());
    d["text"] = utf8(r.to_text());
    return d;
  }, py::arg("mesh"), py::arg("weld_tolerance") = 0.0, py::arg("self_intersections") = true, py::arg("examples") = 5,
        py::arg("threads") = py::none(),
        "The validation report of a mesh (a path, or a (vertices, faces) pair) as `frep check --json` prints it, "
        "as a dict: is_solid, summary, the counts and every defect with examples; text: the report as frep check "
        "prints it.");

  m.def("repair", [](const py::object& mesh, const py::object& output, bool fill_holes, double weld_tolerance,
                     double weld_relative, double time_limit, int resolution, const std::optional<int>& threads) {
    const TriMesh tm = mesh_of(mesh);
    RepairOptions o;
    o.weld_tolerance = weld_tolerance;
    o.weld_relative = weld_relative;
    o.fill_holes = fill_holes;
    o.time_limit = time_limit;
    o.threads = threads_of(threads);
    o.remesh_resolution = resolution;
    std::string out;
    if (!output.is_none()) {
      out = path_of(output);
      // As frep repair: STL stores floats, so the repair works on float coordinates.
      o.float_coordinates = format_from_extension(out) == MeshFormat::Stl || is_device(out);
    }
    RepairResult r;
    {
      py::gil_scoped_release nogil;
      r = make_solid(tm, o);
      if (!out.empty()) write_mesh(out, r.mesh);
    }
    py::dict report = json_dict(repair_report_json(r.report));
    if (!out.empty()) return py::object(report);
    py::tuple arrays = mesh_arrays(std::move(r.mesh));
    return py::object(py::make_tuple(arrays[0], arrays[1], report));
  }, py::arg("mesh"), py::arg("output") = py::none(), py::arg("fill_holes") = true, py::arg("weld_tolerance") = 0.0,
        py::arg("weld_relative") = 1e-7, py::arg("time_limit") = 600.0, py::arg("resolution") = 256,
        py::arg("threads") = py::none(),
        "Makes a mesh (a path, or a (vertices, faces) pair) into the solid it means, as `frep repair` does. With "
        "output: writes it there and returns the report (a dict); without: returns (vertices, faces, report). "
        "Raises frep.InputError if it cannot be repaired.");

  m.def("convert", [](const py::object& mesh, const py::object& output, const std::string& sign, double weld_tolerance,
                      bool repair, const std::optional<int>& threads) {
    const std::string in = path_of(mesh), out = path_of(output);
    check_expression_path(out);
    ConvertOptions o;
    if (sign == "tets") o.sign = SignMode::Tetrahedra;
    else if (sign != "pseudonormal") throw py::value_error("sign is 'pseudonormal' or 'tets', got '" + sign + "'");
    o.weld_tolerance = weld_tolerance;
    o.threads = threads_of(threads);
    ConvertStats s;
    {
      py::gil_scoped_release nogil;
      TriMesh tm = read_mesh(in);
      if (repair) {
        RepairOptions ro;
        ro.threads = o.threads;
        RepairResult r = make_solid(tm, ro);
        r.mesh.name = tm.name;
        tm = std::move(r.mesh);
      }
      ConvertResult r = convert_mesh(tm, o);
      s = r.stats;
      if (std::filesystem::path(out).extension() == ".frep" || is_device(out)) {
        // As frep convert: .frep keeps the triangles beside the closed form (read back, it
        // evaluates through the mesh and writes the same formula again).
        auto closed = std::make_shared<const std::string>(serialize_frep(*r.model.graph, r.model.root, r.model.info));
        save_expression(out, mesh_model(std::make_shared<const MeshOracle>(tm, o, std::move(closed))), &mesh_oracle_codec());
      } else {
        save_expression(out, r.model);
      }
    }
    py::dict d;
    d["triangles"] = s.triangles;
    d["vertices"] = s.vertices;
    d["flat_regions"] = s.flat_regions;
    d["polygons"] = s.polygons;
    d["edge_terms"] = s.edge_terms;
    d["vertex_terms"] = s.vertex_terms;
    d["tetrahedra"] = s.tetrahedra;
    d["nodes"] = s.nodes;
    d["seconds"] = s.seconds;
    return d;
  }, py::arg("mesh"), py::arg("output"), py::arg("sign") = "pseudonormal", py::arg("weld_tolerance") = 0.0,
        py::arg("repair") = false, py::arg("threads") = py::none(),
        "Converts a closed mesh file into an expression of its exact signed distance, written as .vm, .rhai or "
        "(keeping the triangles) .frep, as `frep convert` does; returns the conversion's figures as a dict.");

  m.def("read_mesh", [](const py::object& path) { return mesh_arrays(mesh_of(py::str(path_of(path)))); }, py::arg("path"),
        "(vertices float64 N x 3, faces uint32 M x 3) of a mesh file (.stl, .obj, .ply, .off), as stored (not welded).");
  m.def("write_mesh", [](const py::object& path, const py::array& vertices, const py::array& faces, bool ascii) {
    const std::string p = path_of(path);
    const TriMesh mesh = mesh_of_arrays(vertices, faces, p);
    MeshWriteOptions o;
    o.ascii = ascii;
    py::gil_scoped_release nogil;
    write_mesh(p, mesh, o);
  }, py::arg("path"), py::arg("vertices"), py::arg("faces"), py::arg("ascii") = false,
        "Writes a mesh atomically as .stl (binary, or ascii=True), .obj or .ply, by the extension.");
  m.def("mesh_field", [](const py::array& vertices, const py::array& faces, double weld_tolerance) {
    ConvertOptions o;
    o.weld_tolerance = weld_tolerance;
    const TriMesh mesh = mesh_of_arrays(vertices, faces, "");
    std::shared_ptr<const MeshOracle> oracle;
    {
      py::gil_scoped_release nogil;
      oracle = std::make_shared<const MeshOracle>(mesh, o);
    }
    return PyField::from_model(mesh_model(std::move(oracle)));
  }, py::arg("vertices"), py::arg("faces"), py::arg("weld_tolerance") = 0.0,
        "The exact signed distance of a closed mesh given as arrays (checked as frep check does; refused with "
        "frep.InputError unless a valid solid), as a Field.");
}

}  // namespace frep::python
