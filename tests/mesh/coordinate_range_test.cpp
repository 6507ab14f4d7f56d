// What frep can represent of a mesh's coordinates (frep/mesh/coordinate_range.hpp): the
// tetrahedron with a vertex at 1e30 (its expression read 0 where the distance is 1 or 8) and
// coordinates beyond float range are refused by convert and by mesh fields alike, naming the
// vertex; huge, tiny but well-proportioned meshes, the FLT_MAX box and every shared mesh still
// pass; converted expressions stay finite far away.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include "frep/convert/convert.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/mesh/coordinate_range.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,top), outward, as an OBJ would give it.
TriMesh tall_tet(double top) {
  TriMesh m;
  m.name = "tall.obj";
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, top}};
  m.add_triangle(0, 2, 1, 0, 5);
  m.add_triangle(0, 1, 3, 1, 6);
  m.add_triangle(1, 2, 3, 2, 7);
  m.add_triangle(2, 0, 3, 3, 8);
  return m;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

TEST(CoordinateRange, TetrahedronWithAVertexAt1e30IsRefusedNamingTheVertex) {
  const TriMesh m = tall_tet(1e30);
  const CoordinateSpan s = measure_coordinate_span(m);
  EXPECT_EQ(s.far_vertex, 3u);
  EXPECT_DOUBLE_EQ(s.median_shortest_edge, 1.0);
  EXPECT_NEAR(s.diagonal, 1e30, 1e15);
  const std::string expect = "tall.obj: the mesh spans more than 32-bit floats can carry: vertex 3 (a corner of "
                             "triangle 1, line 6) at (0, 0, 1e+30) makes it 1e+30 across, but half of its triangles "
                             "have an edge shorter than 1, below 2^-20 of that size (9.53674316e+23)";
  std::string e = error_of([&] { convert_mesh(m); });
  EXPECT_TRUE(contains(e, expect)) << e;
  // Mesh fields too: even their double-precision distance is off there (1.005 for 1 below the base).
  e = error_of([&] { MeshField f(m); });
  EXPECT_TRUE(contains(e, expect)) << e;
  // Nearer the limit: a top at 2^19 passes (and converts), one at 2^21 (2^-20 of the size is 2) does not.
  EXPECT_NO_THROW(check_coordinate_range(tall_tet(0x1p19)));
  EXPECT_NO_THROW(convert_mesh(tall_tet(0x1p19)));
  EXPECT_THROW(check_coordinate_range(tall_tet(0x1p21)), InputError);
}

TEST(CoordinateRange, BeyondFloatRangeIsRefusedEverywhereNamingTheVertex) {
  TriMesh m = test::make_box({-1, -1, -1}, {1e39, 1, 1});
  m.name = "wide.obj";
  const std::string expect = "wide.obj: vertex 1 (a corner of triangle 0) at (1e+39, -1, -1) lies beyond the range of "
                             "32-bit floats";
  std::string e = error_of([&] { convert_mesh(m); });
  EXPECT_TRUE(contains(e, expect)) << e;
  e = error_of([&] { MeshField f(m); });
  EXPECT_TRUE(contains(e, expect)) << e;
  // A negative one, an unused one (ignored), a NaN one.
  m = test::make_box({-1, -3.5e38, -1}, {1, 1, 1});
  m.name = "neg.obj";
  EXPECT_TRUE(contains(error_of([&] { MeshField f(m); }), "vertex 0 (a corner of triangle 0) at (-1, -3.5e+38, -1)"));
  m = test::make_box();
  m.vertices.push_back({1e300, 0, 0});
  EXPECT_NO_THROW(check_coordinate_range(m));
  m.vertices[5].y = NAN;
  EXPECT_TRUE(contains(error_of([&] { check_coordinate_range(m); }),
                       "has a coordinate that is not a number"));
}

TEST(CoordinateRange, HugeTinyAndFltMaxMeshesThatAreWellProportionedConvert) {
  for (double size : {1e-30, 1e-6, 1.0, 1e6, 1e30, 1e38}) {
    const TriMesh m = test::make_sphere(1, size);
    EXPECT_NO_THROW(check_coordinate_range(m)) << size;
  }
  // The box with corners at +-FLT_MAX (one face at z = -100), as other tools' stress tests have it.
  const TriMesh flt = test::make_box({-FLT_MAX, -FLT_MAX, -FLT_MAX}, {FLT_MAX, FLT_MAX, -100});
  EXPECT_NO_THROW(check_coordinate_range(flt));
  const ConvertResult r = convert_mesh(flt);
  PointEvaluator pe;
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  // Inside, nearest the bottom face (the top face's z = -100 is below float resolution at this
  // size, about 2e31, as everything within it is).
  EXPECT_NEAR(pe.eval(t, 0, 0, -3e38f), -(FLT_MAX - 3e38), 1e32);
  EXPECT_NEAR(pe.eval(t, 0, 0, 1e38f), 1e38, 1e32);
  // Just below the rounding limit is still a float (FLT_MAX), just above is not.
  const double below = 0x1.fffffefffp127, above = 0x1.ffffffp127;
  EXPECT_NO_THROW(check_coordinate_range(test::make_box({-below, -below, -below}, {below, below, below})));
  EXPECT_THROW(check_coordinate_range(test::make_box({-above, -below, -below}, {below, below, below})), InputError);
}

// Far from its part (2^60 and more of its size units), a converted expression gives the distance
// to within a float's rounding instead of overflowing to inf (it did from about 1.8e19), with a
// unit gradient; nearer, nothing changes (the other convert tests check it bit for bit).
TEST(CoordinateRange, ConvertedExpressionsStayFiniteFarAway) {
  const ConvertResult r = convert_mesh(test::make_box());
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  PointEvaluator pe;
  for (float x : {1e18f, 2e19f, 1e25f, 1e30f, 3e38f}) {
    const float v = pe.eval(t, x, 0, 0), w = pe.eval(t, 0, -x, 0);
    EXPECT_FLOAT_EQ(v, x - 1.0f) << x;
    EXPECT_FLOAT_EQ(w, x - 1.0f) << x;
  }
  const float d = pe.eval(t, 1e20f, 1e20f, 1e20f);
  EXPECT_NEAR(d, std::sqrt(3.0) * (1e20 - 1), 1e-6 * d);
  // Beyond float range the distance itself is inf; nothing is NaN.
  EXPECT_EQ(pe.eval(t, 3e38f, 3e38f, 3e38f), INFINITY);
  GradEvaluator ge;
  const Grad g = ge.eval(t, 0, 0, -1e30f);
  EXPECT_FLOAT_EQ(g.v, 1e30f);
  EXPECT_FLOAT_EQ(g.dz, -1.0f);
  // A scaled mesh (size 1e7: frame units of 2^23) too.
  const ConvertResult big = convert_mesh(test::make_box({-1e7, -1e7, -1e7}, {1e7, 1e7, 1e7}));
  const Tape tb = Tape::compile(*big.model.graph, big.model.root);
  EXPECT_NEAR(pe.eval(tb, 1e30f, 0, 0), 1e30, 1e23);
  EXPECT_EQ(pe.eval(tb, 0, 0, 0), -1e7f);
}

// Every shared mesh that converts passes the rule with a wide margin (the ratio median shortest
// edge / diagonal against 2^-20), and the rule refuses none of the ones that read.
TEST(CoordinateRange, SharedMeshesAreFarFromTheLimit) {
  FREP_REQUIRE_SHARED_MESHES();
  double worst = INFINITY;
  std::string worst_name;
  for (const auto& e : std::filesystem::directory_iterator(test::shared_mesh_dir())) {
    if (format_from_extension(e.path().string()) == MeshFormat::Unknown) continue;
    TriMesh m;
    try {
      m = read_mesh(e.path().string());
    } catch (const InputError&) {
      continue;
    }
    EXPECT_NO_THROW(check_coordinate_range(m)) << e.path();
    const CoordinateSpan s = measure_coordinate_span(m);
    if (s.median_shortest_edge > 0 && s.median_shortest_edge / s.diagonal < worst)
      worst = s.median_shortest_edge / s.diagonal, worst_name = e.path().filename().string();
  }
  std::printf("smallest median shortest edge / diagonal: %.3g (%s), limit %.3g\n", worst, worst_name.c_str(),
              kFloatSpanRatio);
  EXPECT_GT(worst, 100 * kFloatSpanRatio);
}

}  // namespace
}  // namespace frep
