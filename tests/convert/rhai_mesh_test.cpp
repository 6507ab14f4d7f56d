// mesh("file") in Rhai scripts: a mesh file's exact signed distance as a leaf of the script's
// expression, moved by Fidget's shape functions, with errors at the script's line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "frep/convert/convert.hpp"
#include "frep/script/load.hpp"
#include "frep/convert/mesh_oracle.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/script/rhai.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

struct ScriptDir {
  std::filesystem::path dir;
  ScriptDir() {
    dir = std::filesystem::temp_directory_path() / ("frep_rhai_mesh_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir / "parts");
    write_mesh((dir / "parts" / "box.stl").string(), test::make_box());
  }
  ~ScriptDir() { std::filesystem::remove_all(dir); }
  std::string script(const std::string& name, const std::string& text) const {
    const std::string p = (dir / name).string();
    std::ofstream(p) << text;
    return p;
  }
};

float value_at(const Model& m, float x, float y, float z) {
  PointEvaluator pe;
  return pe.eval(Tape::compile(*m.graph, m.root), x, y, z);
}

TEST(RhaiMesh, LoadsAMeshRelativeToTheScriptAndMovesIt) {
  ScriptDir d;
  const Model m = load_field(d.script("a.rhai",
                                      "let part = mesh(\"parts/box.stl\");\n"
                                      "let again = mesh(\"./parts/../parts/box.stl\");\n"
                                      "union(part, move(again, [3.0, 0.0, 0.0])) - 0.25\n"));
  // The box [-1, 1]^3, once more at x + 3, grown by 0.25.
  EXPECT_FLOAT_EQ(value_at(m, 0, 0, 0), -1.25f);
  EXPECT_FLOAT_EQ(value_at(m, 3, 0, 0), -1.25f);
  EXPECT_FLOAT_EQ(value_at(m, 0, 0, 2), 0.75f);
  EXPECT_FLOAT_EQ(value_at(m, 1.5f, 0, 0), 0.25f);
  std::size_t oracles = 0;
  for (NodeId n : reachable_nodes(*m.graph, m.root)) oracles += m.graph->node(n).op == Op::Oracle;
  EXPECT_EQ(oracles, 2u);                   // the box, and the box moved
  EXPECT_EQ(m.graph->oracles().size(), 2u);  // the same file loads once
}

TEST(RhaiMesh, ErrorsNameTheScriptLineOrTheMeshFile) {
  ScriptDir d;
  try {
    load_field(d.script("b.rhai", "let p = mesh(\"parts/box.stl\");\nremap(p, x * x, y, z)\n"));
    ADD_FAILURE() << "a non-affine remap of a mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2u) << e.what();
    EXPECT_NE(std::string(e.what()).find("affine"), std::string::npos) << e.what();
  }
  try {
    load_field(d.script("c.rhai", "mesh(\"parts/missing.stl\")\n"));
    ADD_FAILURE() << "a missing mesh file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("missing.stl"), std::string::npos) << e.what();
  }
  std::ofstream((d.dir / "parts" / "open.obj").string()) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  try {
    load_field(d.script("d.rhai", "mesh(\"parts/open.obj\")\n"));
    ADD_FAILURE() << "an open mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("open.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot convert"), std::string::npos) << e.what();
  }
  // From a string, with no way to load files.
  EXPECT_THROW(parse_rhai("mesh(\"box.stl\")", "inline"), InputError);
  EXPECT_THROW(load_field(d.script("e.rhai", "mesh(3)\n")), InputError);
}

}  // namespace
}  // namespace frep
