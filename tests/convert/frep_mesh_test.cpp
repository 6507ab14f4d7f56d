// .frep files that keep mesh leaves (version 3): the triangles beside the closed form, so that
// reading one back evaluates through the mesh and writes the same formula again.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <sstream>

#include "frep/convert/convert.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/copy.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/vm.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

std::string vm_text(const Graph& g, NodeId root) {
  std::ostringstream s;
  write_vm(s, g, root);
  return s.str();
}

// A mesh, moved, inside an expression: stored as mesh records, read back as mesh leaves, the
// same values and the same closed form.
TEST(FrepMesh, ExpressionsWithMeshesRoundTrip) {
  const TriMesh mesh = test::make_sphere(2, 1.0);
  const auto oracle = std::make_shared<const MeshOracle>(mesh);
  Graph g;
  const Expr x = g.x();
  const Expr m(g, g.oracle(oracle)), moved(g, g.oracle(oracle->transformed(Affine3::translation({1.5, 0, 0}))));
  const NodeId root = (min(m, moved) - 0.1f * x).id();
  const FieldInfo info{1, Box3{{-1, -1, -1}, {2.5, 1, 1}}};
  const std::string bytes = serialize_frep(g, root, info, &mesh_oracle_codec());
  EXPECT_EQ(bytes.substr(8, 4), std::string("\x03\0\0\0", 4));  // version 3
  const Model back = parse_frep(bytes, "t.frep", &mesh_oracle_codec());
  EXPECT_EQ(back.info.lipschitz, 1);
  EXPECT_EQ(back.info.bounds.hi.x, 2.5);
  std::size_t oracles = 0;
  for (NodeId n : reachable_nodes(*back.graph, back.root)) oracles += back.graph->node(n).op == Op::Oracle;
  EXPECT_EQ(oracles, 2u);
  const Tape a = Tape::compile(g, root), b = Tape::compile(*back.graph, back.root);
  PointEvaluator pe;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<float> u(-2, 3);
  for (int i = 0; i < 300; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    EXPECT_EQ(pe.eval(a, p[0], p[1], p[2]), pe.eval(b, p[0], p[1], p[2]));
  }
  EXPECT_TRUE(vm_text(g, root) == vm_text(*back.graph, back.root)) << "the closed forms differ";
  // Without the codec: the closed form, version 2, without oracles, the same field; and a version
  // 3 file needs the codec.
  const std::string closed = serialize_frep(g, root, info);
  EXPECT_EQ(closed.substr(8, 4), std::string("\x02\0\0\0", 4));
  const Model plain = parse_frep(closed, "c.frep");
  EXPECT_FALSE(has_oracles(*plain.graph, plain.root));
  const Tape c = Tape::compile(*plain.graph, plain.root);
  for (int i = 0; i < 300; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    EXPECT_NEAR(pe.eval(c, p[0], p[1], p[2]), pe.eval(a, p[0], p[1], p[2]), 1e-5);
  }
  EXPECT_THROW(parse_frep(bytes, "t.frep"), InputError);
}

// What frep convert writes for .frep: the mesh leaf with the converted closed form, bit for bit.
TEST(FrepMesh, TheClosedFormStaysBitForBit) {
  const TriMesh mesh = test::make_box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
  const ConvertResult r = convert_mesh(mesh);
  auto closed = std::make_shared<const std::string>(serialize_frep(*r.model.graph, r.model.root, r.model.info));
  const Model m = mesh_model(std::make_shared<const MeshOracle>(mesh, ConvertOptions{}, closed));
  const Model back = parse_frep(serialize_frep(*m.graph, m.root, m.info, &mesh_oracle_codec()), "b.frep", &mesh_oracle_codec());
  ASSERT_NE(as_mesh_oracle(*back.graph, back.root), nullptr);
  EXPECT_TRUE(vm_text(*back.graph, back.root) == vm_text(*r.model.graph, r.model.root)) << "the closed form changed";
}

// Damaged records are errors naming the file (the checksum is recomputed, as a tool that edits
// the file would).
TEST(FrepMesh, BadRecordsAreErrors) {
  const auto oracle = std::make_shared<const MeshOracle>(test::make_box());
  const Model m = mesh_model(oracle);
  const std::string good = serialize_frep(*m.graph, m.root, m.info, &mesh_oracle_codec());
  const auto with_crc = [](std::string b) {
    b.resize(b.size() - 4);
    // CRC-32 (zlib's) of the rest, bit by bit.
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char ch : b) {
      c ^= ch;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    c ^= 0xFFFFFFFFu;
    b.append(reinterpret_cast<const char*>(&c), 4);
    return b;
  };
  EXPECT_NO_THROW(parse_frep(with_crc(good), "ok.frep", &mesh_oracle_codec()));
  // The record starts after the header (88 bytes), the record count and its length.
  const std::size_t record = 88 + 4 + 8;
  std::string bad_kind = good;
  bad_kind[record] = 'X';
  EXPECT_THROW(parse_frep(with_crc(bad_kind), "k.frep", &mesh_oracle_codec()), InputError);
  std::string open = good;
  // Corner 0 of the last triangle points at vertex 0: the box is no longer closed.
  const std::size_t name_len = 4 + 4 + oracle->name().size();
  const std::size_t tris = record + name_len + 8 + 4 + 24 * oracle->mesh().vertices.size() + 4;
  const std::size_t last = tris + 12 * (oracle->mesh().triangles.size() - 1);
  std::memset(&open[last], 0, 12);
  try {
    parse_frep(with_crc(open), "o.frep", &mesh_oracle_codec());
    ADD_FAILURE() << "an open mesh record was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "o.frep");
  }
}

}  // namespace
}  // namespace frep
