// The mesher's outputs checked for self-intersections by an independent implementation, CGAL's
// Polygon_mesh_processing::does_self_intersect, alongside frep's own validator (whose triangle
// pair predicate the mesher's repair step also uses: a bug there would pass both).
#include <gtest/gtest.h>


#include <filesystem>
#include <string>
#include <vector>

#include "cgal_test_util.hpp"
#include "contour_test_util.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/script/load.hpp"

namespace frep {
namespace {

// Expressions with sharp features, thin parts and saddles, and the shared models.
TEST(MesherCgal, OutputsDoNotSelfIntersect) {
  std::vector<std::pair<std::string, Model>> models;
  {
    Model m;
    Graph& g = *m.graph;
    auto x = g.x(), y = g.y(), z = g.z();
    // A box with a ball cut out of a corner, and a thin fin: sharp edges, a curved crease.
    const Expr box = max(max(abs(x) - 0.8f, abs(y) - 0.6f), abs(z) - 0.5f);
    const Expr ball = sqrt(square(x - 0.8f) + square(y - 0.6f) + square(z - 0.5f)) - 0.5f;
    const Expr fin = max(max(abs(x) - 0.03f, abs(y) - 0.9f), abs(z) - 0.3f);
    m.root = min(max(box, -ball), fin).id();
    models.emplace_back("box, ball, fin", std::move(m));
  }
  const std::string data = FREP_SOURCE_DIR "/../shared/data";
  for (const char* f : {"/vm/bear.vm", "/meshes/fandisk.obj", "/meshes/bunny_closed_libigl.off"})
    if (std::filesystem::exists(data + f)) models.emplace_back(f, load_field(data + f));
  if (models.size() == 1) std::fprintf(stderr, "../shared/data is absent: only the expression is checked\n");
  for (auto& [name, m] : models) {
    for (const int res : {24, 61}) {
      const MeshOptions o = test::model_options(m, res);
      const TriMesh mesh = mesh_expression(m.root_expr(), o);
      ASSERT_FALSE(mesh.triangles.empty()) << name;
      EXPECT_TRUE(validate_mesh(mesh).is_solid()) << name << " at " << res;
      EXPECT_FALSE(test::cgal_self_intersects(mesh)) << name << " at " << res << ": CGAL finds triangles crossing";
    }
  }
}

}  // namespace
}  // namespace frep
