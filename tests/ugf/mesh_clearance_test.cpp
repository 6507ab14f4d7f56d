// The interference search of two meshes (frep/ugf/mesh_clearance.hpp) as the comparison sets it
// up: seeds at the contacts of crossing boxes or on a nested sphere, the Lipschitz bound for
// meshes in place; and when meeting surfaces only touch.
#include <gtest/gtest.h>

#include <memory>

#include "frep/convert/mesh_oracle.hpp"
#include "frep/expr/copy.hpp"
#include "frep/expr/expr.hpp"
#include "frep/mesh/mesh_field.hpp"
#include "frep/ugf/mesh_clearance.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

// Two mesh leaves in one graph, as frep clearance builds them.
struct TwoMeshes {
  std::shared_ptr<const MeshOracle> a, b;
  Model model;
  NodeId b_root = 0;

  TwoMeshes(const TriMesh& ma, const TriMesh& mb)
      : a(std::make_shared<const MeshOracle>(ma)), b(std::make_shared<const MeshOracle>(mb)), model(mesh_model(a)) {
    const Model m = mesh_model(b);
    b_root = copy_expression(*model.graph, *m.graph, m.root);
  }
  MeshPairResult compare() const { return compare_meshes(a->field(), b->field()); }
  ugf::ClearanceResult search(const Box3& box, const ugf::ClearanceOptions& o) const {
    return ugf::find_clearance(model.root_expr(), Expr(*model.graph, b_root), {float(box.lo.x), float(box.hi.x)},
                               {float(box.lo.y), float(box.hi.y)}, {float(box.lo.z), float(box.hi.z)}, o);
  }
};

TEST(MeshClearance, CrossingBoxesAreSeededAtTheirContacts) {
  const TwoMeshes p(test::make_fine_box(2), test::make_fine_box(2, {0, -0.5, -0.5}, {2, 1.5, 1.5}));
  const MeshPairResult pr = p.compare();
  ASSERT_GT(pr.crossing, 0u);
  ugf::ClearanceOptions o = ugf::mesh_interference_options(pr, true);
  ASSERT_EQ(o.seeds.size(), pr.examples.size());
  for (std::size_t i = 0; i < o.seeds.size(); ++i) EXPECT_EQ(o.seeds[i], Vec3f(pr.examples[i].point));
  EXPECT_EQ(o.lipschitz, 2);
  EXPECT_EQ(ugf::mesh_interference_options(pr, false).lipschitz, 0);
  // The caller's options are kept, its seeds first.
  ugf::ClearanceOptions mine;
  mine.max_boxes = 123;
  mine.seeds.push_back({9, 9, 9});
  o = ugf::mesh_interference_options(pr, true, mine);
  EXPECT_EQ(o.max_boxes, 123u);
  ASSERT_EQ(o.seeds.size(), pr.examples.size() + 1);
  EXPECT_EQ(o.seeds.front(), Vec3f(9, 9, 9));

  // The overlap [0, 1] x [-0.5, 1]^2 is a unit deep along x: A + B = -(1 - x) - x = -1 where
  // both distances are along x (around (0.5, 0.25, 0.25)).
  const Box3 region = ugf::shared_region({{-1, -1, -1}, {1, 1, 1}}, {{0, -0.5, -0.5}, {2, 1.5, 1.5}});
  o = ugf::mesh_interference_options(pr, true);
  o.max_boxes = 4000;
  const ugf::ClearanceResult r = p.search(region, o);
  EXPECT_NEAR(r.value, -1, 1e-4);
  EXPECT_FALSE(ugf::only_touching(pr, r, 1e-4));
}

TEST(MeshClearance, BoxesMeetingAtACornerOnlyTouch) {
  const TwoMeshes p(test::make_fine_box(2), test::make_fine_box(2, {1, 1, 1}, {3, 3, 3}));
  const MeshPairResult pr = p.compare();
  ASSERT_TRUE(pr.surfaces_meet());
  ASSERT_FALSE(pr.interfere());
  ugf::ClearanceOptions o = ugf::mesh_interference_options(pr, true);
  o.max_boxes = 4000;
  const ugf::ClearanceResult r = p.search(ugf::shared_region({{-1, -1, -1}, {1, 1, 1}}, {{1, 1, 1}, {3, 3, 3}}), o);
  EXPECT_GE(r.value, -1e-4f);
  EXPECT_TRUE(ugf::only_touching(pr, r, 1e-4));
  // Found deeper than the tolerance, it is an interference.
  ugf::ClearanceResult deeper = r;
  deeper.value = -1e-3f;
  EXPECT_FALSE(ugf::only_touching(pr, deeper, 1e-4));
}

TEST(MeshClearance, NestedMeshIsSeededOnItsSurface) {
  const TwoMeshes p(test::make_fine_box(3, {-2, -2, -2}, {2, 2, 2}), test::make_sphere(2, 0.5));
  const MeshPairResult pr = p.compare();
  ASSERT_TRUE(pr.b_inside_a());
  const ugf::ClearanceOptions o = ugf::mesh_interference_options(pr, true);
  ASSERT_EQ(o.seeds.size(), 1u);
  EXPECT_EQ(o.seeds[0], Vec3f(pr.point_b));
  // On the ball's surface, inside the box.
  EXPECT_NEAR(p.b->field().signed_distance(pr.point_b), 0, 1e-12);
  EXPECT_LT(p.a->field().signed_distance(pr.point_b), 0);
  // Swapped: the seed is on the nested one, now A.
  const TwoMeshes q(test::make_sphere(2, 0.5), test::make_fine_box(3, {-2, -2, -2}, {2, 2, 2}));
  const MeshPairResult qr = q.compare();
  ASSERT_TRUE(qr.a_inside_b());
  EXPECT_EQ(ugf::mesh_interference_options(qr, true).seeds.at(0), Vec3f(qr.point_a));
  EXPECT_FALSE(ugf::only_touching(qr, {}, 1e-4));
}

}  // namespace
}  // namespace frep
