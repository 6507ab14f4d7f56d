// The 3D renderer: depths of analytic shapes (sphere, box, both cut by the bounds) within the
// refinement tolerance from every view, normals along the analytic ones, the pruned search equal
// to brute-force column search bit for bit (depths, and normals on the shared models) for any
// thread count and tile sizes, and the camera's named views.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "frep/convert/convert.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/render/render3d.hpp"
#include "mesh_test_util.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The inside of a solid along one pixel's column, as an interval of view w (possibly empty).
struct Span {
  double back = kInf, front = -kInf;  // empty by default
  bool empty() const { return !(back < front); }
};

Span intersect(Span a, Span b) { return {std::max(a.back, b.back), std::min(a.front, b.front)}; }

// Points o + w d of the column (d = the camera's `toward`) inside a sphere.
Span sphere_span(Vec3 o, Vec3 d, Vec3 c, double r) {
  const Vec3 oc = o - c;
  const double b = dot(d, oc), disc = b * b - (dot(oc, oc) - r * r);
  if (disc <= 0) return {};
  return {-b - std::sqrt(disc), -b + std::sqrt(disc)};
}

// Points inside an axis-aligned box (slabs).
Span box_span(Vec3 o, Vec3 d, const Box3& box) {
  Span s{-kInf, kInf};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (!(o[a] > box.lo[a] && o[a] < box.hi[a])) return {};
      continue;
    }
    double t0 = (box.lo[a] - o[a]) / d[a], t1 = (box.hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    s = intersect(s, {t0, t1});
  }
  return s;
}

// Checks every pixel of `map` against the analytic inside span of its column, `solid(o, d)`,
// cut by the render bounds. Where a sample lies clearly inside the span the pixel must be a hit
// at the span's front (or at the front sample if the span starts in front of the volume), within
// the bisection bound; where no sample is near the span, no hit.
template <class Solid>
void expect_analytic_depths(const DepthMap& map, const Render3DOptions& o, Solid solid, const std::string& what) {
  const Camera& cam = map.camera;
  const std::vector<float> uc = Camera::centers(cam.u_edges()), vc = Camera::centers(cam.v_edges()), ws = cam.w_samples();
  const double step = 2 * cam.half_w / cam.depth;
  const double tol = step / std::ldexp(1.0, o.refine_steps + 1) + 2e-6;
  int hits = 0, checked = 0, failures = 0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const Vec3 origin = cam.to_model(uc[static_cast<std::size_t>(x)], vc[static_cast<std::size_t>(y)], 0);
      const Span s = intersect(solid(origin, cam.toward), box_span(origin, cam.toward, o.bounds));
      bool clearly_inside = false, near = false;
      for (float w : ws) {
        if (!s.empty() && w > s.back + 1e-5 && w < s.front - 1e-5) clearly_inside = true;
        if (!s.empty() && w > s.back - 1e-5 && w < s.front + 1e-5) near = true;
      }
      const float got = map.depth[map.index(x, y)];
      ++checked;
      if (clearly_inside) {
        ++hits;
        const double want = std::min<double>(s.front, ws[0]);
        if (!(std::fabs(got - want) <= tol) && failures++ < 5)
          ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") depth " << got << ", analytic " << want
                        << " (tolerance " << tol << ")";
      } else if (!near) {
        if (!std::isnan(got) && failures++ < 5)
          ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") hit at " << got << " but the column misses";
      }
    }
  EXPECT_GT(hits, checked / 20) << what << ": the shape should cover part of the image";
}

Render3DOptions options(int size, ViewDirection view, double yaw = 0, double pitch = 0) {
  Render3DOptions o;
  o.size = size;
  o.view = view;
  o.yaw = yaw;
  o.pitch = pitch;
  o.threads = 2;
  return o;
}

Tape sphere_tape(Graph& g, Vec3 c, double r) {
  auto x = g.x(), y = g.y(), z = g.z();
  const Expr e = sqrt(square(x - static_cast<float>(c.x)) + square(y - static_cast<float>(c.y)) +
                      square(z - static_cast<float>(c.z))) -
                 static_cast<float>(r);
  return Tape::compile(g, e.id());
}

TEST(Render3D, SphereDepthsMatchTheAnalyticOnesFromEveryView) {
  Graph g;
  const Vec3 c{0.1, -0.15, 0.2};
  const double r = 0.6;
  const Tape t = sphere_tape(g, c, r);
  auto solid = [&](Vec3 o, Vec3 d) { return sphere_span(o, d, c, r); };
  for (ViewDirection v : {ViewDirection::Front, ViewDirection::Back, ViewDirection::Left, ViewDirection::Right,
                          ViewDirection::Top, ViewDirection::Bottom, ViewDirection::Iso}) {
    const Render3DOptions o = options(72, v);
    expect_analytic_depths(render3d(t, o), o, solid, std::string("sphere, view ") + view_direction_name(v));
  }
  Render3DOptions o = options(80, ViewDirection::Front, 30, -20);
  o.bounds = Box3{{-1.2, -0.8, -1}, {1, 1, 0.9}};
  o.refine_steps = 2;
  expect_analytic_depths(render3d(t, o), o, solid, "sphere, rotated, uneven bounds, 2 refine steps");
  o.refine_steps = 0;
  o.depth_steps = 23;
  expect_analytic_depths(render3d(t, o), o, solid, "sphere, no refinement, 23 depth steps");
}

TEST(Render3D, SphereCutByTheBounds) {
  // A sphere larger than the bounds: from the iso view the cube's corners are cut off, and the
  // cut faces are flat, with the bounds' face normals.
  Graph g;
  const Tape t = sphere_tape(g, {0, 0, 0}, 1.3);
  const Render3DOptions o = options(64, ViewDirection::Iso);
  const DepthMap map = render3d(t, o);
  expect_analytic_depths(map, o, [](Vec3 p, Vec3 d) { return sphere_span(p, d, {0, 0, 0}, 1.3); }, "cut sphere");
  const Camera& cam = map.camera;
  const Vec3 faces[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // the iso view sees +x, +y, +z
  int on_faces = 0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      if (!map.hit(x, y)) continue;
      const Vec3f n = map.normal[map.index(x, y)];
      const Vec3 model = cam.right * n.x + cam.up * n.y + cam.toward * n.z;
      for (const Vec3& f : faces)
        if (dot(model, f) > 0.999) ++on_faces;
    }
  EXPECT_GT(on_faces, map.width() * map.height() / 10);
}

// A model that is one mesh (moved or not) is rendered by casting rays through its triangles: the
// same picture as the column search of the same field, up to a depth step, and with the same
// pixels hit but for a few on silhouettes and sample-thin slivers; cut by the bounds too.
TEST(Render3D, MeshesAreRenderedByRaysLikeTheirColumnSearch) {
  const auto sphere = std::make_shared<const MeshOracle>(test::make_sphere(3, 0.8));
  Affine3 moved = Affine3::translation({0.1, -0.2, 0.05});
  moved.m[0][0] = 1.4;  // stretched along x too
  struct Case {
    std::shared_ptr<const Oracle> oracle;
    Render3DOptions o;
    const char* what;
  };
  Render3DOptions cut = options(96, ViewDirection::Iso);
  cut.bounds = Box3{{-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}};  // cuts the sphere: flat caps
  const Case cases[] = {{sphere, options(96, ViewDirection::Front), "front"},
                        {sphere, options(96, ViewDirection::Iso, 20, 10), "rotated"},
                        {sphere, cut, "cut by the bounds"},
                        {sphere->transformed(moved), options(96, ViewDirection::Iso), "moved and stretched"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Graph g;
    const NodeId leaf = g.oracle(c.oracle);
    const Tape rays = Tape::compile(g, leaf);
    // The same field with one more instruction: searched by columns.
    const Tape columns = Tape::compile(g, (Expr(g, leaf) + 0.0f * g.x()).id());
    ASSERT_EQ(rays.size(), 1u);
    ASSERT_GT(columns.size(), 1u);
    const DepthMap a = render3d(rays, c.o), b = render3d(columns, c.o);
    const Camera& cam = a.camera;
    const double step = 2 * cam.half_w / cam.depth;
    std::size_t hits = 0, disagree = 0, far = 0, turned = 0;
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x) {
        const std::size_t i = a.index(x, y);
        if (a.hit(x, y) != b.hit(x, y)) {
          ++disagree;
          continue;
        }
        if (!a.hit(x, y)) continue;
        ++hits;
        far += std::fabs(double(a.depth[i]) - b.depth[i]) > step;
        const Vec3f na = a.normal[i], nb = b.normal[i];
        turned += double(na.x) * nb.x + double(na.y) * nb.y + double(na.z) * nb.z < 0.9;
      }
    EXPECT_GT(hits, 1000u);
    EXPECT_LE(disagree, hits / 100);
    EXPECT_EQ(far, 0u);
    EXPECT_LE(turned, hits / 100);
  }
}

TEST(Render3D, RotatedBoxDepths) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Box3 box{{-0.5, -0.3, -0.6}, {0.7, 0.4, 0.2}};
  const Vec3 c = box.center(), h = box.size() * 0.5;
  const Expr e = max(max(abs(x - static_cast<float>(c.x)) - static_cast<float>(h.x),
                         abs(y - static_cast<float>(c.y)) - static_cast<float>(h.y)),
                     abs(z - static_cast<float>(c.z)) - static_cast<float>(h.z));
  const Tape t = Tape::compile(g, e.id());
  auto solid = [&](Vec3 o, Vec3 d) { return box_span(o, d, box); };
  for (auto [yaw, pitch] : {std::pair{0.0, 0.0}, {25.0, 10.0}, {-130.0, 55.0}}) {
    const Render3DOptions o = options(64, ViewDirection::Iso, yaw, pitch);
    expect_analytic_depths(render3d(t, o), o, solid, "box, iso + " + std::to_string(yaw) + "," + std::to_string(pitch));
  }
}

TEST(Render3D, SphereNormalsPointRadially) {
  Graph g;
  const Vec3 c{-0.1, 0.05, 0.1};
  const double r = 0.7;
  const Tape t = sphere_tape(g, c, r);
  for (ViewDirection v : {ViewDirection::Front, ViewDirection::Iso}) {
    const DepthMap map = render3d(t, options(v == ViewDirection::Iso ? 96 : 64, v, 10, 5));
    const Camera& cam = map.camera;
    const std::vector<float> uc = Camera::centers(cam.u_edges()), vc = Camera::centers(cam.v_edges());
    int checked = 0;
    double worst = 0;
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) {
        if (!map.hit(x, y)) continue;
        const std::size_t p = map.index(x, y);
        // The normal at the point found (whose depth is checked above): along the radius.
        Vec3 m = cam.to_model(uc[static_cast<std::size_t>(x)], vc[static_cast<std::size_t>(y)], map.depth[p]) - c;
        EXPECT_NEAR(length(m), r, 1e-3);
        m = m / length(m);
        const Vec3 want{dot(m, cam.right), dot(m, cam.up), dot(m, cam.toward)};
        const Vec3f n = map.normal[p];
        EXPECT_NEAR(std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z), 1.0, 1e-5);
        worst = std::max({worst, std::fabs(n.x - want.x), std::fabs(n.y - want.y), std::fabs(n.z - want.z)});
        ++checked;
      }
    EXPECT_GT(checked, 500);
    EXPECT_LT(worst, 2e-5) << view_direction_name(v);
  }
}

// A converted mesh is sqrt of a squared distance: its gradient is exactly 0 where a located
// point lands on the surface (sqrt'(0) = 0). Every hit still gets its face's normal (an earlier
// version fell back to facing the viewer there: flat faces came out striped).
TEST(Render3D, NormalsOfExactDistancesWhereTheHitIsOnTheSurface) {
  const ConvertResult r = convert_mesh(test::make_box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}));
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  const DepthMap map = render3d(t, options(96, ViewDirection::Iso, 10, 5));
  const Camera& cam = map.camera;
  int checked = 0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      if (!map.hit(x, y)) continue;
      const Vec3f n = map.normal[map.index(x, y)];
      double best = 1e9;
      for (int axis = 0; axis < 3; ++axis)
        for (double s : {-1.0, 1.0}) {
          Vec3 m{0, 0, 0};
          m[axis] = s;
          const Vec3 want{dot(m, cam.right), dot(m, cam.up), dot(m, cam.toward)};
          best = std::min(best, std::fabs(n.x - want.x) + std::fabs(n.y - want.y) + std::fabs(n.z - want.z));
        }
      EXPECT_LT(best, 1e-4) << "pixel " << x << ", " << y << ": normal " << n.x << " " << n.y << " " << n.z;
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

bool same_value(float a, float b) { return test::same_value(a, b); }

// Depths (and, if `normals`, normals) bit for bit.
std::string first_difference(const DepthMap& a, const DepthMap& b, bool normals) {
  if (a.width() != b.width() || a.height() != b.height()) return "sizes differ";
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const std::size_t p = a.index(x, y);
      if (!same_value(a.depth[p], b.depth[p]))
        return "depth at (" + std::to_string(x) + ", " + std::to_string(y) + "): " + test::fstr(a.depth[p]) + " vs " +
               test::fstr(b.depth[p]);
      if (normals && !(same_value(a.normal[p].x, b.normal[p].x) && same_value(a.normal[p].y, b.normal[p].y) &&
                       same_value(a.normal[p].z, b.normal[p].z)))
        return "normal at (" + std::to_string(x) + ", " + std::to_string(y) + ")";
    }
  return "";
}

std::vector<Render3DOptions> variants(Render3DOptions base) {
  std::vector<Render3DOptions> v;
  for (int threads : {1, 2, 3}) {
    base.threads = threads;
    v.push_back(base);
  }
  base.threads = 2;
  for (std::vector<int> tiles : {std::vector<int>{16, 4}, {8, 4, 2}, {5, 3, 1}, {256}}) {
    base.tiles = tiles;
    v.push_back(base);
  }
  return v;
}

void expect_equals_brute_force(const Tape& t, const Render3DOptions& base, bool normals, const std::string& what) {
  const DepthMap ref = render3d_brute_force(t, base);
  for (const Render3DOptions& o : variants(base)) {
    const std::string diff = first_difference(render3d(t, o), ref, normals);
    EXPECT_TRUE(diff.empty()) << what << ", threads " << o.threads << ", tiles " << ::testing::PrintToString(o.tiles)
                              << ": " << diff;
  }
}

TEST(Render3D, EqualsBruteForceOnTheSharedModels) {
  FREP_REQUIRE_DATA("bear.vm");
  FREP_REQUIRE_DATA("tanglecube.vm");
  const Model bear = load_expression(test::data_file("bear.vm"));
  const Tape tb = Tape::compile(*bear.graph, bear.root);
  expect_equals_brute_force(tb, options(36, ViewDirection::Front), true, "bear, front");
  Render3DOptions o = options(30, ViewDirection::Iso, 20, -10);
  o.depth_steps = 41;
  expect_equals_brute_force(tb, o, true, "bear, rotated iso");
  const Model tangle = load_expression(test::data_file("tanglecube.vm"));
  o = options(32, ViewDirection::Iso);
  o.bounds = Box3{{-4, -4, -4}, {4, 4, 4}};
  expect_equals_brute_force(Tape::compile(*tangle.graph, tangle.root), o, true, "tanglecube");
}

TEST(Render3D, EqualsBruteForceOnRandomExpressions) {
  // Depths only: a simplified tape folds an instruction whose interval is one value into a
  // constant, which can change a gradient (not a value).
  std::mt19937_64 rng(311);
  for (int e = 0; e < 40; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 4 + e % 3;
    opt.special_const_prob = 0.02;
    opt.const_range = 1.5f;
    test::ExprGen gen(g, rng, opt);
    const Tape t = Tape::compile(g, gen.gen());
    Render3DOptions o = options(18, e % 2 ? ViewDirection::Iso : ViewDirection::Top, e % 3 * 15.0);
    o.tiles = {8, 2};
    const DepthMap ref = render3d_brute_force(t, o);
    for (int threads : {1, 3}) {
      o.threads = threads;
      const std::string diff = first_difference(render3d(t, o), ref, false);
      ASSERT_TRUE(diff.empty()) << "random expression #" << e << ", threads " << threads << ": " << diff;
    }
  }
}

// With a Lipschitz bound (exact distances: converted meshes, a sphere), boxes also settle from
// their centre's value: the picture stays the brute-force one bit for bit, from rotated views
// too (the view is a rotation), for any thread count and tiles.
TEST(Render3D, LipschitzBoundOnExactDistancesEqualsBruteForce) {
  std::vector<std::pair<std::string, ConvertResult>> meshes;
  meshes.emplace_back("converted box", convert_mesh(test::make_box({-0.5, -0.4, -0.6}, {0.6, 0.5, 0.3})));
  meshes.emplace_back("converted sphere", convert_mesh(test::make_sphere(2, 0.7)));
  for (const auto& [name, r] : meshes) {
    ASSERT_EQ(r.model.info.lipschitz, 1.0) << "a converted mesh is an exact distance";
    const Tape t = Tape::compile(*r.model.graph, r.model.root);
    for (auto [view, yaw] : {std::pair{ViewDirection::Front, 0.0}, {ViewDirection::Iso, 17.0}}) {
      Render3DOptions o = options(40, view, yaw);
      o.lipschitz = 1;
      expect_equals_brute_force(t, o, true, name);
    }
  }
  Graph g;
  Render3DOptions o = options(48, ViewDirection::Iso, -30, 10);
  o.lipschitz = 1;
  expect_equals_brute_force(sphere_tape(g, {0.1, -0.2, 0.05}, 0.6), o, true, "sphere");
}

// A true bound below 1 (a scaled distance): a rotated view is cut by max(f, box), whose box part
// has slope 1, so the renderer settles with max(L, 1). It used to settle with L and lose half of
// the sphere (cut or not).
TEST(Render3D, LipschitzBoundBelowOneEqualsBruteForce) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Tape t = Tape::compile(g, ((sqrt(square(x) + square(y) + square(z)) - 0.6f) * 0.1f).id());
  for (double yaw : {0.0, 30.0}) {
    Render3DOptions o = options(48, yaw == 0 ? ViewDirection::Front : ViewDirection::Iso, yaw);
    o.lipschitz = 0.1;
    expect_equals_brute_force(t, o, true, "sphere scaled by 0.1");
  }
}

// A Lipschitz bound the field breaks (a user's wrong --lipschitz, or an exact distance whose
// float evaluation flips a sign) settles boxes inside whose front neighbours find no crossing:
// the picture may be wrong, but every pixel with an inside sample still gets a depth, and the
// render does not stop with an internal error (it did, on `frep shell` output of a CAD plate).
TEST(Render3D, ABrokenLipschitzBoundGivesAPictureNotAnInternalError) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Expr r = sqrt(square(x) + square(y) + square(z)) - 0.5f;
  const Expr f = sin(r * 20.0f) * 20.0f + r;  // slopes up to about 400
  const Tape t = Tape::compile(g, f.id());
  Render3DOptions o = options(96, ViewDirection::Iso);
  o.lipschitz = 1;
  DepthMap m;
  ASSERT_NO_THROW(m = render3d(t, o));
  int hits = 0;
  for (float d : m.depth) hits += d == d;
  EXPECT_GT(hits, 0);
}

TEST(Render3D, RendererIsReusableAndBruteForceRowStep) {
  Graph g;
  const Tape a = sphere_tape(g, {0, 0, 0}, 0.5), b = sphere_tape(g, {0.3, 0, 0}, 0.4);
  Renderer3D r(options(32, ViewDirection::Iso));
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(first_difference(r.render(a), render3d_brute_force(a, r.options()), true), "");
    EXPECT_EQ(first_difference(r.render(b), render3d_brute_force(b, r.options()), true), "");
  }
  // Every 3rd row: those rows equal the full brute force, the others are empty.
  const DepthMap full = render3d_brute_force(a, r.options()), sampled = render3d_brute_force(a, r.options(), 3);
  int hits = 0;
  for (int y = 0; y < full.height(); ++y)
    for (int x = 0; x < full.width(); ++x) {
      const std::size_t p = full.index(x, y);
      if (y % 3 == 0) EXPECT_TRUE(same_value(full.depth[p], sampled.depth[p]));
      else EXPECT_FALSE(sampled.hit(x, y));
      hits += full.hit(x, y);
    }
  EXPECT_GT(hits, 50);
}

TEST(Render3D, EmptyFullAndNanFields) {
  Graph g;
  const Render3DOptions o = options(16, ViewDirection::Iso);
  const DepthMap empty = render3d(Tape::compile(g, g.constant(1)), o);
  for (float d : empty.depth) EXPECT_TRUE(std::isnan(d));
  const DepthMap nan = render3d(Tape::compile(g, g.constant(std::numeric_limits<float>::quiet_NaN())), o);
  for (float d : nan.depth) EXPECT_TRUE(std::isnan(d)) << "NaN is not inside";
  // Everything inside: the bounds cube itself, cut at its faces, from the front: every pixel at
  // the front of the volume, facing the viewer.
  const DepthMap full = render3d(Tape::compile(g, g.constant(-1)), options(16, ViewDirection::Front));
  for (std::size_t p = 0; p < full.depth.size(); ++p) {
    EXPECT_EQ(full.depth[p], 1.0f);
    EXPECT_EQ(full.normal[p].z, 1.0f);
  }
}

// Regions near the end of the float range: pixel centres between edges near FLT_MAX used to
// overflow to infinity (a pixel with an inside sample and no hit: an internal error); a view
// volume beyond floats is an InputError, as are grids and meshes there.
TEST(Render3D, RegionsNearTheFloatRange) {
  const double big = 3.4e38;
  const ConvertResult r = convert_mesh(test::make_box({-big, -big, -big}, {big, big, -100}));
  const Tape t = Tape::compile(*r.model.graph, r.model.root);
  Render3DOptions o = options(24, ViewDirection::Front);
  o.bounds = Box3{{-3e38, -3e38, -3e38}, {3e38, 3e38, 3e38}};
  const DepthMap map = render3d(t, o);
  EXPECT_EQ(first_difference(map, render3d_brute_force(t, o), true), "");
  int hits = 0;
  for (float d : map.depth) hits += !std::isnan(d);
  EXPECT_GT(hits, 0);
  o.view = ViewDirection::Iso;  // its view volume's diagonal is beyond floats
  EXPECT_THROW(render3d(t, o), InputError);
}

TEST(Render3D, InvalidOptionsThrow) {
  Graph g;
  const Tape t = Tape::compile(g, g.var_x());
  Render3DOptions o;
  o.size = 0;
  EXPECT_THROW(render3d(t, o), InputError);
  o.size = 16;
  o.tiles = {4, 8};
  EXPECT_THROW(render3d(t, o), InputError);
  o.tiles = {8, 4};
  o.bounds = Box3{{0, 0, 0}, {1, 0, 1}};
  EXPECT_THROW(render3d(t, o), InputError);
  o.bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
  o.refine_steps = -1;
  EXPECT_THROW(render3d_brute_force(t, o), InputError);
}

TEST(Camera, NamedViewsAreExactRightHandedFrames) {
  struct Want {
    ViewDirection v;
    Vec3 right, up, toward;
  };
  const Want wants[] = {
      {ViewDirection::Front, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {ViewDirection::Back, {-1, 0, 0}, {0, 1, 0}, {0, 0, -1}},
      {ViewDirection::Right, {0, 0, -1}, {0, 1, 0}, {1, 0, 0}}, {ViewDirection::Left, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}},
      {ViewDirection::Top, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}},   {ViewDirection::Bottom, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
  };
  const Box3 unit{{-1, -1, -1}, {1, 1, 1}};
  for (const Want& w : wants) {
    double yaw = 0, pitch = 0;
    view_angles(w.v, yaw, pitch);
    const Camera c = make_camera(unit, yaw, pitch, 10);
    EXPECT_EQ(c.right, w.right) << view_direction_name(w.v);
    EXPECT_EQ(c.up, w.up) << view_direction_name(w.v);
    EXPECT_EQ(c.toward, w.toward) << view_direction_name(w.v);
    EXPECT_TRUE(c.axis_aligned);
    EXPECT_EQ(c.width, 10);
    EXPECT_EQ(c.depth, 10);
    ViewDirection parsed{};
    EXPECT_TRUE(parse_view_direction(view_direction_name(w.v), parsed));
    EXPECT_EQ(parsed, w.v);
  }
  double yaw = 0, pitch = 0;
  view_angles(ViewDirection::Iso, yaw, pitch);
  const Camera iso = make_camera(unit, yaw, pitch, 100);
  EXPECT_FALSE(iso.axis_aligned);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(iso.toward[a], 1 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(length(iso.right - cross(iso.up, iso.toward)), 0, 1e-12) << "right-handed";
  // The cube's silhouette from (1,1,1) is a hexagon 2 sqrt(2) wide and 4 sqrt(2/3) tall.
  // (The narrower side is rounded up to whole square pixels.)
  const double pixel = 4 * std::sqrt(2.0 / 3) / 100;
  EXPECT_NEAR(iso.half_v, 2 * std::sqrt(2.0 / 3), 1e-9);
  EXPECT_EQ(iso.height, 100);
  EXPECT_EQ(iso.width, static_cast<int>(std::ceil(2 * std::sqrt(2.0) / pixel)));
  EXPECT_NEAR(iso.half_u, iso.width * pixel / 2, 1e-9);
  EXPECT_GE(iso.half_u, std::sqrt(2.0));
  ViewDirection v{};
  EXPECT_FALSE(parse_view_direction("sideways", v));
  // Turning the front view by yaw 90 gives the right view.
  const Camera turned = make_camera(unit, 90, 0, 10);
  EXPECT_EQ(turned.toward, (Vec3{1, 0, 0}));
}

TEST(Camera, ZUpViews) {
  // CAD's convention: front looks from -y with z up, right from +x, top from +z with y up.
  struct Want {
    ViewDirection v;
    Vec3 right, up, toward;
  };
  const Want wants[] = {
      {ViewDirection::Front, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}}, {ViewDirection::Right, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
      {ViewDirection::Back, {-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},  {ViewDirection::Top, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
      {ViewDirection::Bottom, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
  };
  const Box3 box{{-1, -2, -3}, {1, 2, 3}};
  for (const Want& w : wants) {
    double yaw = 0, pitch = 0;
    view_angles(w.v, yaw, pitch);
    const Camera c = make_camera(box, yaw, pitch, 60, 0, true);
    EXPECT_EQ(c.right, w.right) << view_direction_name(w.v);
    EXPECT_EQ(c.up, w.up) << view_direction_name(w.v);
    EXPECT_EQ(c.toward, w.toward) << view_direction_name(w.v);
    EXPECT_EQ(cross(c.right, c.up), c.toward) << "right-handed";
  }
  // The front view of the box shows x (2 wide) by z (6 tall), 2 deep.
  const Camera front = make_camera(box, 0, 0, 60, 0, true);
  EXPECT_EQ(front.height, 60);
  EXPECT_EQ(front.width, 20);
  EXPECT_EQ(front.depth, 40);
}

TEST(Render3D, ZUpSphereDepths) {
  Graph g;
  const Vec3 c{0.2, 0.1, -0.3};
  const Tape t = sphere_tape(g, c, 0.5);
  for (ViewDirection v : {ViewDirection::Front, ViewDirection::Iso}) {
    Render3DOptions o = options(48, v);
    o.z_up = true;
    expect_analytic_depths(render3d(t, o), o, [&](Vec3 p, Vec3 d) { return sphere_span(p, d, c, 0.5); },
                           std::string("z up, ") + view_direction_name(v));
  }
}

}  // namespace
}  // namespace frep
