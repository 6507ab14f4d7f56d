// 3MF output: a round trip through lib3mf, and the file's XML read independently of lib3mf
// (Python's zipfile and a count of the XML elements), as a slicer would see it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "cli_test_util.hpp"
#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/validate.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

TEST(Mesh3mf, RoundTripKeepsEveryTriangleAndFloatCoordinates) {
  TriMesh m = test::make_sphere(2, 1.5);
  for (Vec3& v : m.vertices) v = v + Vec3{1e3, -2, 0.1};
  const std::string bytes = write_3mf(m);
  EXPECT_EQ(sniff_format(bytes), MeshFormat::ThreeMf);
  const TriMesh back = read_mesh_from_memory(bytes, "mem.3mf");
  ASSERT_EQ(back.triangles.size(), m.triangles.size());
  ASSERT_EQ(back.vertices.size(), m.vertices.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) EXPECT_EQ(back.triangles[t], m.triangles[t]);
  // The file holds each float coordinate cut to six decimals: exactly what as_3mf_stores says.
  const TriMesh expected = as_3mf_stores(m);
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(back.vertices[v][c], expected.vertices[v][c]);
      EXPECT_LE(std::fabs(back.vertices[v][c] - m.vertices[v][c]), 1e-6 + 1.2e-7 * std::fabs(m.vertices[v][c])); // cut, float
    }
  EXPECT_TRUE(validate_mesh(back).is_solid());
}

TEST(Mesh3mf, RefusesWhatItCannotStore) {
  TriMesh m = test::make_box();
  m.vertices[0].x = 1e300;  // beyond single precision
  EXPECT_THROW(write_3mf(m), InputError);
  EXPECT_THROW(read_mesh_from_memory(std::string("PK\x03\x04garbage", 11), "bad.3mf"), InputError);
  EXPECT_EQ(length_unit_from_name("inch"), LengthUnit::Inch);
  EXPECT_FALSE(length_unit_from_name("furlong").has_value());
}

// What a slicer reads: the model XML inside the zip, with its unit and one <triangle> per
// triangle. Read with Python's zipfile, not lib3mf, so that a bug in how frep drives lib3mf
// cannot pass both sides.
TEST(Mesh3mf, CliWritesUnitsAndTrianglesAnyZipReaderSees) {
  if (std::system("/usr/bin/python3 -c 'import zipfile' 2>/dev/null") != 0) GTEST_SKIP() << "no /usr/bin/python3 to unzip with";
  test::ScratchDir dir;
  const std::string stl = dir.path("box.stl"), out = dir.path("box.3mf");
  write_mesh(stl, test::make_box({0, 0, 0}, {20, 10, 5}));
  test::CliRun r = test::run_frep(dir, "mesh " + test::shell_quote(stl) + " -o " + test::shell_quote(out) + " -r 16 -q --units inch");
  ASSERT_EQ(r.code, 0) << r.err;
  const TriMesh written = read_mesh(out);
  EXPECT_TRUE(validate_mesh(written).is_solid());
  const std::string script = dir.path("count.py");
  test::write_text(script,
                   "import re, sys, zipfile\n"
                   "x = zipfile.ZipFile(sys.argv[1]).read('3D/3dmodel.model').decode()\n"
                   "print(re.search(r'unit=\"(\\w+)\"', x).group(1), x.count('<triangle '))\n");
  const std::string log = dir.path("count.txt");
  ASSERT_EQ(std::system(("/usr/bin/python3 " + test::shell_quote(script) + " " + test::shell_quote(out) + " > " +
                         test::shell_quote(log))
                            .c_str()),
            0);
  EXPECT_EQ(test::read_text(log), "inch " + std::to_string(written.triangles.size()) + "\n");
  // A unit nobody knows is refused before any work.
  r = test::run_frep(dir, "mesh " + test::shell_quote(stl) + " -o " + test::shell_quote(dir.path("x.3mf")) + " --units furlong");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("furlong"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace frep
