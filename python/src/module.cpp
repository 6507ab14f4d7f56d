// The extension module frep._core: errors as Python exceptions, the thread count, and the shared
// helpers of common.hpp; the functions and classes are bound by the other compile units.
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "common.hpp"
#include "frep/error.hpp"
#include "frep/expr/copy.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep::python {

namespace {
std::atomic<int> g_threads{0};
}  // namespace

int threads_of(const std::optional<int>& threads) {
  const int t = threads ? *threads : g_threads.load();
  if (t < 0) throw py::value_error("threads must be >= 0 (0: all cores), got " + std::to_string(t));
  return t;
}
void set_default_threads(int threads) {
  if (threads < 0) throw py::value_error("threads must be >= 0 (0: all cores), got " + std::to_string(threads));
  g_threads = threads;
}
int default_threads() { return g_threads.load(); }

PyField PyField::from_model(Model m) {
  const Field f = field_of(m);
  return PyField(std::shared_ptr<Graph>(std::move(m.graph)), f);
}

Field PyField::in_graph_of(const PyField& other) const {
  if (graph == other.graph) return field;
  Graph& to = *other.graph;
  Field f(Expr(to, copy_expression(to, *graph, field.id())), field.info);
  if (field.affine_source != kNoNode) {
    // Keeps the chain of transforms composable, as in the graph it came from.
    f.affine_source = copy_expression(to, *graph, field.affine_source);
    f.affine = field.affine;
  }
  return f;
}

SameGraph same_graph(const PyField& a, const PyField& b) {
  if (a.graph == b.graph) return {a.graph, a.field, b.field};
  // Copy the smaller expression graph into the larger one.
  if (a.graph->size() >= b.graph->size()) return {a.graph, a.field, b.in_graph_of(a)};
  return {b.graph, a.in_graph_of(b), b.field};
}

Points points_of(const py::object& given) {
  const py::array points = py::array::ensure(given);
  if (!points) throw py::error_already_set();
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw py::value_error("points must be an N x 3 array, got shape " + std::string(py::str(points.attr("shape"))));
  const std::size_t n = static_cast<std::size_t>(points.shape(0));
  Points p;
  p.x.resize(n);
  p.y.resize(n);
  p.z.resize(n);
  // One pass over the caller's memory (any strides): float32 read as it is, float64 rounded
  // once; other dtypes (integers) are converted to float64 by NumPy first.
  auto split = [&](auto arr) {
    auto r = arr.template unchecked<2>();
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = static_cast<py::ssize_t>(i);
      p.x[i] = static_cast<float>(r(k, 0));
      p.y[i] = static_cast<float>(r(k, 1));
      p.z[i] = static_cast<float>(r(k, 2));
    }
  };
  if (points.dtype().is(py::dtype::of<float>()))
    split(py::array_t<float>(points));
  else
    split(py::array_t<double>(points));
  return p;
}

Vec3 vec3_of(const py::handle& v, const char* what) {
  const auto s = py::cast<std::vector<double>>(v);
  if (s.size() != 3) throw py::value_error(std::string(what) + " needs three numbers (x, y, z)");
  return {s[0], s[1], s[2]};
}

Box3 box_of(const py::handle& bounds) {
  std::vector<double> v;
  const auto outer = py::cast<std::vector<py::object>>(bounds);
  if (outer.size() == 2) {
    const Vec3 lo = vec3_of(outer[0], "bounds' lower corner"), hi = vec3_of(outer[1], "bounds' upper corner");
    v = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
  } else {
    v = py::cast<std::vector<double>>(bounds);
  }
  if (v.size() != 6)
    throw py::value_error("bounds are (x0, y0, z0, x1, y1, z1) or ((x0, y0, z0), (x1, y1, z1))");
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(v[a]) || !std::isfinite(v[a + 3]) || !(v[a] < v[a + 3]))
      throw py::value_error("bounds need finite numbers with x0 < x1, y0 < y1, z0 < z1");
  return Box3{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
}

std::optional<Box3> optional_box(const py::object& bounds) {
  if (bounds.is_none()) return std::nullopt;
  return box_of(bounds);
}

py::tuple box_tuple(const Box3& b) {
  return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z), py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
}

py::str utf8(const std::string& s) {
  return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(s.data(), static_cast<py::ssize_t>(s.size()), "replace"));
}

void bind_errors(py::module_& m) {
  // frep.InputError: bad input (a file, an argument), a ValueError carrying where the problem is.
  py::handle type = PyErr_NewExceptionWithDoc(
      "frep.InputError",
      "Bad input: a file or argument frep cannot use. A ValueError with the place of the problem:\n"
      "file (str, empty for in-memory input), line (int, 0 when unknown), byte (int, offset in binary\n"
      "files, 0 when unknown) and detail (the message without the place).",
      PyExc_ValueError, nullptr);
  if (!type) throw py::error_already_set();
  m.attr("InputError") = type;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::object t = py::module_::import("frep._core").attr("InputError");
      py::object exc = t(utf8(e.what()));
      exc.attr("file") = utf8(e.file());
      exc.attr("line") = e.line();
      exc.attr("byte") = e.byte_offset();
      exc.attr("detail") = utf8(e.detail());
      PyErr_SetObject(t.ptr(), exc.ptr());
    } catch (const InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError, (std::string("frep internal error (a bug): ") + e.what()).c_str());
    }
  });
}

}  // namespace frep::python

PYBIND11_MODULE(_core, m) {
  using namespace frep::python;
  m.doc() = "frep's C++ library: exact signed distances of meshes and expressions, modeling, meshing, rendering";
  bind_errors(m);
  m.def("set_threads", &set_default_threads, py::arg("threads"),
        "Sets the worker threads every call uses unless given threads= (0: all cores, the default).");
  m.def("get_threads", &default_threads, "The thread count set by set_threads (0: all cores).");
  m.def("hardware_threads", [] { return frep::resolve_thread_count(0); }, "The number of hardware threads.");
  bind_field(m);
  bind_sampling(m);
  bind_modeling(m);
  bind_files(m);
}
