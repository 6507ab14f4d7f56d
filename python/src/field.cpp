// frep.Field: values, gradients and intervals of a field, what is known of it (FieldInfo), saving,
// and Python's operators building expressions. Heavy work runs without the GIL on a compiled tape.
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>

#include "common.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/expr/expr.hpp"
#include "frep/model/csg.hpp"
#include "frep/script/save.hpp"
#include "frep/ugf/offset.hpp"

namespace frep::python {
namespace {

const char* growth_name(Growth g) {
  switch (g) {
    case Growth::Box: return "box";
    case Growth::Distance: return "distance";
    case Growth::Unknown: break;
  }
  return "unknown";
}

// A number or a field as a field of `like`'s graph (numbers become constants there).
Field operand(const py::object& o, const PyField& like) {
  if (py::isinstance<PyField>(o)) return py::cast<const PyField&>(o).in_graph_of(like);
  return Field(like.graph->c(py::cast<float>(o)));
}

using ExprOp = Expr (*)(Expr, Expr);
// a op b on expressions, nothing known of the result.
PyField arithmetic(const PyField& a, const py::object& b, ExprOp op, bool reflected) {
  if (py::isinstance<PyField>(b)) {
    const SameGraph s = same_graph(a, py::cast<const PyField&>(b));
    return PyField(s.graph, Field(reflected ? op(s.b.expr, s.a.expr) : op(s.a.expr, s.b.expr)));
  }
  const Field k = operand(b, a);
  return a.with(Field(reflected ? op(k.expr, a.field.expr) : op(a.field.expr, k.expr)));
}

Expr add(Expr a, Expr b) { return a + b; }
Expr sub(Expr a, Expr b) { return a - b; }
Expr mul(Expr a, Expr b) { return a * b; }
Expr div(Expr a, Expr b) { return a / b; }

py::array_t<float> evaluate(const PyField& f, const py::object& points, const std::optional<int>& threads) {
  const Points p = points_of(points);
  const Tape tape = f.tape();
  py::array_t<float> out(static_cast<py::ssize_t>(p.size()));
  float* o = out.mutable_data();
  PointCloudOptions po;
  po.threads = threads_of(threads);
  {
    py::gil_scoped_release nogil;
    PointCloudEvaluator ev(po);
    ev.eval(tape, p.x.data(), p.y.data(), p.z.data(), o, p.size());
  }
  return out;
}

}  // namespace

void bind_field(py::module_& m) {
  py::class_<FieldInfo>(m, "FieldInfo",
                        "What is known of a field: every stated fact is true; unknown ones are 0 or None.")
      .def_readonly("lipschitz", &FieldInfo::lipschitz,
                    "A bound L on |f(p) - f(q)| / |p - q| (1 for exact distances), or 0 if unknown.")
      .def_property_readonly(
          "bounds", [](const FieldInfo& i) -> py::object { return i.bounds.empty() ? py::object(py::none()) : box_tuple(i.bounds); },
          "A box ((x0, y0, z0), (x1, y1, z1)) holding every point where the field is negative, or None.")
      .def_property_readonly(
          "growth", [](const FieldInfo& i) { return growth_name(i.growth); },
          "How small values grow beyond the box: 'box' (f < t lies in the box grown by t), 'distance' "
          "(moreover f is at least the distance to the inside), or 'unknown'.")
      .def("__repr__", [](const FieldInfo& i) {
        std::string b = "None";
        if (!i.bounds.empty()) b = std::string(py::str(box_tuple(i.bounds)));
        return "FieldInfo(lipschitz=" + std::string(py::str(py::float_(i.lipschitz))) + ", bounds=" + b +
               ", growth='" + growth_name(i.growth) + "')";
      });

  py::class_<PyField> cls(m, "Field",
                          "A field: an expression (negative inside) with what is known of it (info). Made by "
                          "frep.load, the modeling functions and arithmetic on fields and numbers.");
  cls.def_property_readonly("info", [](const PyField& f) { return f.field.info; },
                            "What is known of the field (FieldInfo: lipschitz, bounds, growth).")
      .def_property_readonly("is_mesh", [](const PyField& f) { return as_mesh_oracle(*f.graph, f.field.id()) != nullptr; },
                             "True if the field is a mesh's exact signed distance (moved or not), evaluated through the mesh.")
      .def("sdf", &evaluate, py::arg("points"), py::arg("threads") = py::none(),
           "The field's values (float32, N) at an N x 3 array of points (float32 used as given, float64 rounded "
           "once to float32). For meshes, the exact signed distance rounded to float32, negative inside.")
      .def("__call__", &evaluate, py::arg("points"), py::arg("threads") = py::none(), "The same as sdf(points).")
      .def(
          "gradient",
          [](const PyField& f, const py::object& points, const std::optional<int>& threads) {
            const Points p = points_of(points);
            const Tape tape = f.tape();
            const std::size_t n = p.size();
            py::array_t<float> out({static_cast<py::ssize_t>(n), py::ssize_t(3)});
            float* o = out.mutable_data();
            PointCloudOptions po;
            po.threads = threads_of(threads);
            {
              py::gil_scoped_release nogil;
              std::vector<Grad> g(n);
              PointCloudEvaluator ev(po);
              ev.eval_grad(tape, p.x.data(), p.y.data(), p.z.data(), g.data(), n);
              for (std::size_t i = 0; i < n; ++i) {
                o[3 * i] = g[i].dx;
                o[3 * i + 1] = g[i].dy;
                o[3 * i + 2] = g[i].dz;
              }
            }
            return out;
          },
          py::arg("points"), py::arg("threads") = py::none(),
          "The gradient (float32, N x 3: d/dx, d/dy, d/dz) at an N x 3 array of points, by forward-mode "
          "differentiation (where it does not exist, the side a min or max returns).")
      .def(
          "interval",
          [](const PyField& f, const py::object& bounds) {
            const Box3 b = box_of(bounds);
            const Tape tape = f.tape();
            IntervalEvaluator ev;
            const Interval r = ev.eval(tape, {static_cast<float>(b.lo.x), static_cast<float>(b.hi.x)},
                                       {static_cast<float>(b.lo.y), static_cast<float>(b.hi.y)},
                                       {static_cast<float>(b.lo.z), static_cast<float>(b.hi.z)});
            return py::make_tuple(r.lo, r.hi);
          },
          py::arg("bounds"),
          "(lo, hi): an interval holding every value of the field over the box ((x0, y0, z0), (x1, y1, z1)), "
          "by interval arithmetic (NaN, NaN when unknown).")
      .def(
          "save",
          [](const PyField& f, const std::filesystem::path& path) {
            // Meshes stay meshes in .frep files (the triangles beside the closed form).
            save_expression(path.string(), *f.graph, f.field.id(), f.field.info, &mesh_oracle_codec());
          },
          py::arg("path"),
          "Saves the expression as .vm (Fidget's text format), .rhai (a Fidget script) or .frep (frep's binary "
          "format), with its facts in the file.")
      .def("__repr__", [](const PyField& f) {
        return "<frep.Field lipschitz=" + std::string(py::str(py::float_(f.field.info.lipschitz))) +
               (f.field.info.bounds.empty() ? std::string(" unbounded") : " bounds=" + std::string(py::str(box_tuple(f.field.info.bounds)))) +
               ">";
      });

  // Operators: numbers next to fields become constants. f + c and f - c are offsets (their facts
  // follow, frep/ugf/offset.hpp), -f the complement; the rest know nothing of their result.
  cls.def("__add__", [](const PyField& a, const py::object& b) {
       if (!py::isinstance<PyField>(b)) return a.with(ugf::offset(a.field, -py::cast<float>(b)));
       return arithmetic(a, b, add, false);
     }, py::is_operator())
      .def("__radd__", [](const PyField& a, const py::object& b) {
        return a.with(ugf::offset(a.field, -py::cast<float>(b)));
      }, py::is_operator())
      .def("__sub__", [](const PyField& a, const py::object& b) {
        if (!py::isinstance<PyField>(b)) return a.with(ugf::offset(a.field, py::cast<float>(b)));
        return arithmetic(a, b, sub, false);
      }, py::is_operator())
      .def("__rsub__", [](const PyField& a, const py::object& b) { return arithmetic(a, b, sub, true); }, py::is_operator())
      .def("__mul__", [](const PyField& a, const py::object& b) { return arithmetic(a, b, mul, false); }, py::is_operator())
      .def("__rmul__", [](const PyField& a, const py::object& b) { return arithmetic(a, b, mul, true); }, py::is_operator())
      .def("__truediv__", [](const PyField& a, const py::object& b) { return arithmetic(a, b, div, false); }, py::is_operator())
      .def("__rtruediv__", [](const PyField& a, const py::object& b) { return arithmetic(a, b, div, true); }, py::is_operator())
      .def("__neg__", [](const PyField& a) { return a.with(inverse(a.field)); })
      .def("__abs__", [](const PyField& a) { return a.with(Field(abs(a.field.expr))); })
      .def("__or__", [](const PyField& a, const PyField& b) {
        const SameGraph s = same_graph(a, b);
        return PyField(s.graph, unite(s.a, s.b));
      }, py::is_operator(), "a | b: the union min(a, b).")
      .def("__and__", [](const PyField& a, const PyField& b) {
        const SameGraph s = same_graph(a, b);
        return PyField(s.graph, intersect(s.a, s.b));
      }, py::is_operator(), "a & b: the intersection max(a, b).");
}

}  // namespace frep::python
