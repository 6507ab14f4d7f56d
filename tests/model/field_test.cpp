// The modeling API (frep/model/*.hpp): shapes against their formulas computed here in double,
// the facts every operation claims checked by sampling random compositions, the composition of
// transforms, the Rhai builtins building the same expressions, and the facts kept in files.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <sstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/tape.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/script/rhai.hpp"
#include "frep/io/vm.hpp"
#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/model/transform.hpp"
#include "frep/ugf/blend.hpp"
#include "frep/ugf/boolean.hpp"
#include "frep/ugf/offset.hpp"

namespace frep {
namespace {

Vec3 normalize(const Vec3& v) { return v * (1 / length(v)); }

TEST(ModelShapes, MatchTheirFormulas) {
  Graph g;
  const Field s = sphere(g, {1, -2, 0.5}, 1.5);
  const Field b = box(g, {-1, 0, 2}, {2, 1, 3});
  const Field c = circle(g, 0.5, 0.25, 2);
  const Field pl = plane(g, {0, 0.6, 0.8}, 0.5);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  const Tape ts = Tape::compile(g, s.id()), tb = Tape::compile(g, b.id()), tc = Tape::compile(g, c.id()),
             tp = Tape::compile(g, pl.id());
  PointEvaluator pe;
  for (int i = 0; i < 500; ++i) {
    const Vec3 p{static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))};
    const double ds = std::sqrt((p.x - 1) * (p.x - 1) + (p.y + 2) * (p.y + 2) + (p.z - 0.5) * (p.z - 0.5)) - 1.5;
    const double db = std::max({-1 - p.x, p.x - 2, 0 - p.y, p.y - 1, 2 - p.z, p.z - 3});
    const double dc = std::hypot(p.x - 0.5, p.y - 0.25) - 2;
    const double dp = 0.6 * p.y + 0.8 * p.z - 0.5;
    const auto at = [&](const Tape& t) { return pe.eval(t, float(p.x), float(p.y), float(p.z)); };
    EXPECT_NEAR(at(ts), ds, 1e-5);
    EXPECT_NEAR(at(tb), db, 1e-5);
    EXPECT_NEAR(at(tc), dc, 1e-5);
    EXPECT_NEAR(at(tp), dp, 1e-5);
  }
  EXPECT_EQ(s.info.lipschitz, 1);
  EXPECT_EQ(s.info.growth, Growth::Distance);
  EXPECT_EQ(b.info.growth, Growth::Box);
  EXPECT_TRUE(c.info.bounds.empty()) << "a circle is an infinite cylinder along z";
}

// A random composition of every modeling operation, and a description for failure messages.
struct Built {
  Field f;
  std::string what;
};

Built random_field(Graph& g, std::mt19937& rng, int depth) {
  std::uniform_real_distribution<double> u(-1, 1), pos(0.2, 1.2);
  std::uniform_int_distribution<int> pick(0, depth <= 0 ? 1 : 16);
  const auto v3 = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  switch (pick(rng)) {
    case 0: return {sphere(g, v3(), pos(rng)), "sphere"};
    case 1: {
      const Vec3 lo = v3();
      return {box(g, lo, lo + Vec3{pos(rng), pos(rng), pos(rng)}), "box"};
    }
    default: break;
  }
  const Built a = random_field(g, rng, depth - 1);
  std::uniform_int_distribution<int> op(0, 17);
  switch (op(rng)) {
    case 0: {
      const Built b = random_field(g, rng, depth - 1);
      return {unite(a.f, b.f), "union(" + a.what + ", " + b.what + ")"};
    }
    case 1: {
      const Built b = random_field(g, rng, depth - 1);
      return {intersect(a.f, b.f), "intersection(" + a.what + ", " + b.what + ")"};
    }
    case 2: {
      const Built b = random_field(g, rng, depth - 1);
      return {subtract(a.f, b.f), "difference(" + a.what + ", " + b.what + ")"};
    }
    case 3: {
      const Built b = random_field(g, rng, depth - 1);
      return {blend(a.f, b.f, pos(rng)), "blend(" + a.what + ", " + b.what + ")"};
    }
    case 4: return {move(a.f, v3()), "move(" + a.what + ")"};
    case 5: {
      const Vec3 axis = normalize(v3() + Vec3{0, 0, 0.01});
      return {rotate(a.f, axis, 180 * u(rng), v3()), "rotate(" + a.what + ")"};
    }
    case 6: return {scale(a.f, {pos(rng), pos(rng), pos(rng)}), "scale(" + a.what + ")"};
    case 7: return {reflect(a.f, normalize(v3() + Vec3{0.01, 0, 0}), u(rng)), "reflect(" + a.what + ")"};
    case 8: return {ugf::offset(a.f, static_cast<float>(0.5 * u(rng))), "offset(" + a.what + ")"};
    case 9: return {ugf::shell(a.f, static_cast<float>(0.3 * pos(rng))), "shell(" + a.what + ")"};
    case 10: return {ugf::shell_outward(a.f, static_cast<float>(0.3 * pos(rng))), "shell_outward(" + a.what + ")"};
    case 11: return {ugf::shell_inward(a.f, static_cast<float>(0.3 * pos(rng))), "shell_inward(" + a.what + ")"};
    case 12: {
      const Built b = random_field(g, rng, depth - 1);
      return {ugf::smooth_union(a.f, b.f, static_cast<float>(0.5 * pos(rng)), ugf::Blend::Exponential),
              "smooth_union(" + a.what + ", " + b.what + ")"};
    }
    case 13: {
      const Built b = random_field(g, rng, depth - 1);
      return {ugf::intersect_exact(a.f, b.f), "intersect_exact(" + a.what + ", " + b.what + ")"};
    }
    case 14: {
      const Built b = random_field(g, rng, depth - 1);
      return {ugf::unite_exact(a.f, b.f), "unite_exact(" + a.what + ", " + b.what + ")"};
    }
    case 15: return {extrude_z(a.f, -0.5, 0.5 + pos(rng)), "extrude_z(" + a.what + ")"};
    case 16: {
      const Built b = random_field(g, rng, depth - 1);
      return {ugf::subtract_right_angle(a.f, b.f), "subtract_right_angle(" + a.what + ", " + b.what + ")"};
    }
    default: return {inverse(inverse(a.f)), "inverse(inverse(" + a.what + "))"};
  }
}

// Every fact a composition claims holds at sampled points: its Lipschitz bound over pairs of
// points (near and far), its box (non-negative outside), and its growth (at least t outside the
// box grown by t). The margins cover f32 evaluation only.
TEST(ModelFacts, HoldAtSampledPointsForRandomCompositions) {
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> u(-3.5, 3.5), unit(-1, 1), t_dist(0, 1.5);
  int with_bounds = 0, with_growth = 0, with_bound = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Graph g;
    const Built b = random_field(g, rng, 3);
    const FieldInfo& info = b.f.info;
    const Tape tape = Tape::compile(g, b.f.id());
    PointEvaluator pe;
    const auto f = [&](const Vec3& p) { return pe.eval(tape, float(p.x), float(p.y), float(p.z)); };
    const double slack = 2e-5;
    if (info.lipschitz > 0) {
      ++with_bound;
      for (int i = 0; i < 300; ++i) {
        const Vec3 p{u(rng), u(rng), u(rng)};
        const double step = i % 2 ? 1e-2 : 1.0;
        const Vec3 q = p + Vec3{step * unit(rng), step * unit(rng), step * unit(rng)};
        const double fp = f(p), fq = f(q);
        if (!std::isfinite(fp) || !std::isfinite(fq)) continue;
        ASSERT_LE(std::fabs(fp - fq), info.lipschitz * length(p - q) * (1 + 1e-6) + slack)
            << b.what << " at " << p.x << "," << p.y << "," << p.z;
      }
    }
    if (info.bounds.empty()) continue;
    ++with_bounds;
    with_growth += info.growth != Growth::Unknown;
    const Box3 outer = info.bounds.inflated(3);
    std::uniform_real_distribution<double> ux(outer.lo.x, outer.hi.x), uy(outer.lo.y, outer.hi.y), uz(outer.lo.z, outer.hi.z);
    for (int i = 0; i < 600; ++i) {
      const Vec3 p{ux(rng), uy(rng), uz(rng)};
      const float fp = f(p);
      if (!info.bounds.contains(p)) {
        ASSERT_GE(fp, -slack) << b.what << ": negative outside its bounds";
      }
      if (info.growth == Growth::Unknown) continue;
      const double t = t_dist(rng);
      if (!info.bounds.inflated(t).contains(p)) {
        ASSERT_GE(fp, t - slack) << b.what << ": below " << t << " outside bounds + t";
      }
    }
  }
  // The generator must exercise the facts, not skip them.
  EXPECT_GT(with_bound, 100);
  EXPECT_GT(with_bounds, 100);
  EXPECT_GT(with_growth, 50);
}

TEST(ModelFacts, RulesOnUnknowns) {
  FieldInfo known;
  known.lipschitz = 1;
  known.bounds = {{0, 0, 0}, {1, 1, 1}};
  known.growth = Growth::Distance;
  const FieldInfo unknown;
  EXPECT_EQ(union_info(known, unknown).lipschitz, 0) << "a union is as unknown as its least known part";
  EXPECT_TRUE(union_info(known, unknown).bounds.empty());
  EXPECT_FALSE(intersection_info(known, unknown).bounds.empty()) << "an intersection lies in either known box";
  EXPECT_EQ(intersection_info(known, known).growth, Growth::Box) << "a wedge's max is not a distance";
  EXPECT_TRUE(inverse_info(known).bounds.empty());
  EXPECT_EQ(offset_info(known, 0.5).bounds.hi.x, 1.5);
  EXPECT_EQ(offset_info(known, -0.5).growth, Growth::Box) << "shrinking can remove thin parts";
  FieldInfo no_growth = known;
  no_growth.growth = Growth::Unknown;
  EXPECT_TRUE(offset_info(no_growth, 0.5).bounds.empty()) << "growing a box needs a known growth";
  // Disjoint boxes: an empty inside, which a box cannot state: unknown, not a made-up box.
  FieldInfo far = known;
  far.bounds = {{5, 5, 5}, {6, 6, 6}};
  EXPECT_TRUE(intersection_info(known, far).bounds.empty());
}

TEST(ModelTransforms, ChainsComposeIntoOneRemap) {
  Graph g;
  const Field s = sphere(g, {0, 0, 0}, 1);
  const Field twice = move(move(s, {1, 2, 3}), {0.5, -1, 0.25});
  const Field once = move(s, {1.5, 1, 3.25});
  EXPECT_EQ(twice.id(), once.id()) << "composed maps build the single move's nodes";
  EXPECT_EQ(twice.affine_source, s.id());
  EXPECT_EQ(twice.info.growth, Growth::Distance);
  EXPECT_NEAR(twice.info.bounds.lo.x, 0.5, 1e-9);
  // A rotation keeps a distance a distance, and so does shrinking the shape (f(2p) = 2|p| - 1 is
  // at least |p| - 1/2); enlarging it does not (f(p/2) = |p|/2 - 1 is below |p| - 2).
  EXPECT_EQ(rotate(s, {0, 0, 1}, 30).info.growth, Growth::Distance);
  EXPECT_EQ(scale(s, {0.5, 0.5, 0.5}).info.growth, Growth::Distance);
  EXPECT_EQ(scale(s, {2, 2, 2}).info.growth, Growth::Unknown);
  EXPECT_NEAR(scale(s, {0.5, 0.5, 0.5}).info.lipschitz, 2, 1e-9);
  // A rotated box: its box is the rotated corners' hull, and no growth survives 45 degrees.
  const Field b = rotate(box(g, {-1, -1, -1}, {1, 1, 1}), {0, 0, 1}, 45);
  EXPECT_NEAR(b.info.bounds.hi.x, std::sqrt(2.0), 1e-9);
  EXPECT_EQ(b.info.growth, Growth::Unknown);
}

TEST(ModelCsg, FieldsFromTwoGraphsAreRefused) {
  Graph g1, g2;
  EXPECT_THROW(unite(sphere(g1, {0, 0, 0}, 1), sphere(g2, {0, 0, 0}, 1)), std::invalid_argument);
}

// The script builtins bind the library: a script and the same C++ give the same values.
TEST(ModelRhai, ScriptsBuildWhatTheLibraryBuilds) {
  const Model m = parse_rhai(R"(
    let a = sphere(#{ center: [0.5, 0, 0], radius: 1 });
    let b = box([-1, -0.5, -0.5], [0.5, 0.5, 0.5]).rotate_z(90).move([0, 0.25, 0]);
    blend(a, b, 0.2).scale([1, 2, 1])
  )");
  Graph g;
  const Field a = sphere(g, {0.5, 0, 0}, 1);
  const Field b = move(rotate(box(g, {-1, -0.5, -0.5}, {0.5, 0.5, 0.5}), {0, 0, 1}, 90), {0, 0.25, 0});
  const Field cpp = scale(blend(a, b, 0.2), {1, 2, 1});
  const Tape ts = Tape::compile(*m.graph, m.root), tc = Tape::compile(g, cpp.id());
  PointEvaluator pe;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 200; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    const float vs = pe.eval(ts, x, y, z), vc = pe.eval(tc, x, y, z);
    ASSERT_EQ(std::bit_cast<std::uint32_t>(vs), std::bit_cast<std::uint32_t>(vc)) << x << "," << y << "," << z;
  }
  // And the script's model carries the same facts.
  EXPECT_EQ(m.info.lipschitz, cpp.info.lipschitz);
  EXPECT_EQ(m.info.bounds.lo.x, cpp.info.bounds.lo.x);
  EXPECT_EQ(m.info.bounds.hi.y, cpp.info.bounds.hi.y);
  EXPECT_GT(m.info.lipschitz, 0);
  EXPECT_FALSE(m.info.bounds.empty());
}

TEST(ModelRhai, CommentsOverrideAndFillFacts) {
  // The author's comment wins where it speaks; the library fills in the rest.
  const Model m = parse_rhai("// frep: lipschitz 0.5\nsphere(#{ center: [0, 0, 0], radius: 2 })");
  EXPECT_EQ(m.info.lipschitz, 0.5);
  EXPECT_EQ(m.info.bounds.hi.x, 2);
  EXPECT_EQ(m.info.growth, Growth::Distance);
  // Plain arithmetic carries no facts.
  const Model plain = parse_rhai("x * x + y - 1");
  EXPECT_EQ(plain.info.lipschitz, 0);
  EXPECT_TRUE(plain.info.bounds.empty());
}

TEST(ModelFiles, GrowthSurvivesEveryFormat) {
  Graph g;
  const Field s = ugf::offset(sphere(g, {0, 0, 0}, 1), 0.5f);
  for (const Growth growth : {Growth::Box, Growth::Distance}) {
    FieldInfo info = s.info;
    info.growth = growth;
    const Model f = parse_frep(serialize_frep(g, s.id(), info), "mem.frep");
    EXPECT_EQ(f.info.growth, growth);
    std::ostringstream vm, rhai;
    write_vm(vm, g, s.id(), info);
    write_rhai(rhai, g, s.id(), info);
    EXPECT_EQ(parse_vm(vm.str(), "mem.vm").info.growth, growth);
    EXPECT_EQ(parse_rhai(rhai.str(), "mem.rhai").info.growth, growth);
  }
  EXPECT_THROW(parse_vm("# frep: bounds 0 0 0 1 1 1\n# frep: growth far\n0 var-x\n", "bad.vm"), InputError);
}

}  // namespace
}  // namespace frep
