// What the binding's compile units share: a Field that keeps its graph alive, the thread count,
// NumPy arrays that own C++ vectors, and the points of an N x 3 array.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frep/eval/tape.hpp"
#include "frep/expr/model.hpp"
#include "frep/math/vec.hpp"
#include "frep/model/field.hpp"

namespace frep::python {

namespace py = pybind11;

// A field as Python holds it: the Field and the graph its expression lives in, shared by every
// field built from it (graphs only grow, so sharing is safe while the GIL is held).
struct PyField {
  std::shared_ptr<Graph> graph;
  Field field;

  PyField(std::shared_ptr<Graph> g, const Field& f) : graph(std::move(g)), field(f) {}
  // Takes over a loaded model's graph.
  static PyField from_model(Model m);
  // A new field in a graph of its own, built by `make` (the modeling functions' shapes).
  template <class Make>
  static PyField make(Make&& make) {
    auto g = std::make_shared<Graph>();
    Field f = make(*g);
    return PyField(std::move(g), f);
  }
  // This field in the same graph as `other`: itself if it is there already, else copied over
  // (frep/expr/copy.hpp), facts and affine source included.
  Field in_graph_of(const PyField& other) const;
  // A result of this field's graph.
  PyField with(const Field& f) const { return PyField(graph, f); }
  // Compiled (under the GIL: the graph may grow from another thread while work runs without it).
  Tape tape() const { return Tape::compile(*graph, field.id()); }
};

// Two fields in one graph: the one with the larger graph keeps its own, the other is copied in.
struct SameGraph {
  std::shared_ptr<Graph> graph;
  Field a, b;
};
SameGraph same_graph(const PyField& a, const PyField& b);

// The thread count of a call: `threads` if given, else the one set by frep.set_threads (0: all cores).
int threads_of(const std::optional<int>& threads);
void set_default_threads(int threads);
int default_threads();

// A 1-D or 2-D NumPy array that owns `v` (moved into it, no copy). `shape` must cover v.size().
template <class T>
py::array_t<T> own_vector(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free_when_done);
}

// Points of an N x 3 array (or anything NumPy makes one of) of float32 (used as they are) or
// float64 (rounded once), split into the x, y, z arrays the evaluators read.
struct Points {
  std::vector<float> x, y, z;
  std::size_t size() const { return x.size(); }
};
Points points_of(const py::object& points);

// A box from (x0, y0, z0, x1, y1, z1) or ((x0, y0, z0), (x1, y1, z1)); throws ValueError unless
// finite with lo < hi on every axis.
Box3 box_of(const py::handle& bounds);
std::optional<Box3> optional_box(const py::object& bounds);
Vec3 vec3_of(const py::handle& v, const char* what);
// (lo, hi) as two tuples of three numbers.
py::tuple box_tuple(const Box3& b);

// A Python str from bytes that should be UTF-8 (file names, messages): invalid bytes replaced.
py::str utf8(const std::string& s);

// The binding's parts, each in its own compile unit.
void bind_errors(py::module_& m);
void bind_field(py::module_& m);
void bind_sampling(py::module_& m);
void bind_modeling(py::module_& m);
void bind_files(py::module_& m);

}  // namespace frep::python
