#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

std::string binary_stl(const std::vector<std::array<float, 9>>& tris, const char* header, std::uint32_t count) {
  std::string s(80, '\0');
  std::memcpy(s.data(), header, std::min<std::size_t>(80, std::strlen(header)));
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : tris) {
    float n[3] = {NAN, 0, 0};  // normals are ignored, even NaN ones
    s.append(reinterpret_cast<const char*>(n), 12);
    s.append(reinterpret_cast<const char*>(t.data()), 36);
    s.append(2, '\0');
  }
  return s;
}

// Expects an InputError whose message contains `what`, and returns it for more checks.
template <class F>
InputError expect_input_error(F&& f, const std::string& what) {
  try {
    f();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    return e;
  }
  ADD_FAILURE() << "no InputError (expected one mentioning '" << what << "')";
  return InputError("", 0, "");
}

TEST(MeshIo, BinaryStlWithSolidHeaderAndWrongCount) {
  std::vector<std::array<float, 9>> tris = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, 0, 0, 1}};
  // Header starts with "solid" (as SolidWorks writes): the size decides it is binary.
  TriMesh m = read_mesh_from_memory(binary_stl(tris, "solid part", 2), "a.stl");
  EXPECT_EQ(m.num_triangles(), 2u);
  EXPECT_FALSE(m.indexed);
  EXPECT_EQ(m.vertices[4], (Vec3{0, 1, 0}));
  // The count field says 7 but the size holds exactly 2 facets: trust the size.
  m = read_stl(binary_stl(tris, "solid part", 7), "b.stl");
  EXPECT_EQ(m.num_triangles(), 2u);
  ASSERT_EQ(m.warnings.size(), 2u);  // ...and say so: the file may have lost triangles
  EXPECT_EQ(m.warnings[0], "binary STL header declares 7 triangles but the file holds 2 (truncated file?); read 2");
  EXPECT_NE(m.warnings[1].find("2 facet normals are NaN or infinite"), std::string::npos) << m.warnings[1];
  // Count 1 with trailing bytes that are not a whole facet: read the declared facet.
  std::string padded = binary_stl(tris, "x", 1) + "abc";
  EXPECT_EQ(read_stl(padded, "c.stl").num_triangles(), 1u);
  // Truncated inside a facet: error with the byte offset of the incomplete facet.
  std::string cut = binary_stl(tris, "x", 2);
  cut.resize(cut.size() - 7);
  InputError e = expect_input_error([&] { read_stl(cut, "d.stl"); }, "d.stl: byte 134: binary STL truncated");
  EXPECT_EQ(e.byte_offset(), 134u);
  // Another text format under an .stl name is not "truncated binary".
  expect_input_error([] { read_stl("_0 var-x\n_1 const 1\n_2 sub _0 _1\n", "f.stl"); }, "f.stl: not an STL file: text");
  std::string long_text(500, 'a');
  expect_input_error([&] { read_stl(long_text, "g.stl"); }, "g.stl: not an STL file: text");
  expect_input_error([] { read_stl("\xEF\xBB\xBF// caf\xC3\xA9\nx - 1\n", "h.stl"); }, "h.stl: not an STL file: text");
  // NaN coordinate.
  tris[1][4] = NAN;
  expect_input_error([&] { read_stl(binary_stl(tris, "x", 2), "e.stl"); }, "byte 162: vertex coordinate is not a finite");
}

TEST(MeshIo, AsciiStlVariants) {
  // CRLF, upper-case keywords, zero and NaN normals, two solids, mismatched and missing endsolid.
  const std::string text =
      "solid one\r\n facet normal 0 0 0\r\n  outer loop\r\n   vertex 0 0 0\r\n   vertex 1 0 0\r\n"
      "   vertex 0 1 0\r\n  endloop\r\n endfacet\r\nendsolid other\r\n"
      "SOLID two\nFACET NORMAL nan nan nan\nOUTER LOOP\nVERTEX 0 0 1\nVERTEX 1e0 0 1\nVERTEX 0 +1 1\nENDLOOP\n"
      "ENDFACET\n";
  TriMesh m = read_mesh_from_memory(text, "x.obj");  // content wins over a lying extension
  ASSERT_EQ(m.num_triangles(), 2u);
  EXPECT_EQ(m.vertices[4], (Vec3{1, 0, 1}));
  EXPECT_EQ(m.origins[1].line, 11u);
  expect_input_error([] { read_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zz\n", "f.stl"); },
                     "f.stl:4: bad vertex coordinate 'zz'");
  expect_input_error([] { read_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 inf\n", "f.stl"); },
                     "f.stl:4: vertex coordinate is not a finite");
  expect_input_error([] { read_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "g.stl"); },
                     "g.stl:4: ASCII STL ends inside a facet loop");
  expect_input_error([] { read_stl("solid x\nendsolid x\n", "h.stl"); }, "no facets");
}

TEST(MeshIo, ObjPolygonsNegativeIndicesAndContinuations) {
  const std::string text =
      "# comment\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3/1/1 4/1/1\n"  // quad -> 2 triangles
      "f -4//1 -2//1 \\\r\n -1//1\n"  // negative indices, continuation line
      "g group\ns off\nusemtl m\n";
  TriMesh m = read_obj(text, "a.obj");
  ASSERT_EQ(m.num_triangles(), 3u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (Triangle{0, 2, 3}));
  EXPECT_EQ(m.origins[1].face, 0u);
  EXPECT_EQ(m.origins[2].line, 10u);
  expect_input_error([] { read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "b.obj"); }, "b.obj:4: face index 4 is beyond");
  expect_input_error([] { read_obj("v 0 0 0\nf -2 1 1\n", "c.obj"); }, "c.obj:2: relative face index");
  expect_input_error([] { read_obj("v 0 0 nan\n", "d.obj"); }, "d.obj:1: vertex coordinate is not a finite");
  expect_input_error([] { read_obj("v 0 0 0\n", "e.obj"); }, "no faces");
  expect_input_error([] { read_obj(std::string("\x01\x02garbage\n", 10), "g.obj"); }, "g.obj:1: not an OBJ statement");
}

std::string ply_header(const char* format, const char* vertex_props, int nv, const char* faces) {
  return std::string("ply\nformat ") + format + " 1.0\ncomment test\nelement vertex " + std::to_string(nv) + "\n" +
         vertex_props + faces + "end_header\n";
}

TEST(MeshIo, PlyAsciiAndBinaryBothEndians) {
  // Property order z, extra, x, y; faces a quad; a tristrip element too.
  const char* props = "property float z\nproperty uchar red\nproperty double x\nproperty float y\n";
  const char* faces =
      "element face 1\nproperty list uchar int vertex_indices\n"
      "element tristrips 1\nproperty list int int vertex_indices\n";
  std::string ascii = ply_header("ascii", props, 4, faces) +
                      "0 255 0 0\n0 1 1 0\n0 2 1 1\n0 3 0 1\n4 0 1 2 3\n6 0 1 3 -1 1 2\n";
  TriMesh a = read_ply(ascii, "a.ply");
  ASSERT_EQ(a.vertices.size(), 4u);
  EXPECT_EQ(a.vertices[2], (Vec3{1, 1, 0}));
  // Quad -> 2 triangles; strip [0 1 3] -> 1 triangle; [1 2] -> none.
  ASSERT_EQ(a.num_triangles(), 3u);
  EXPECT_EQ(a.triangles[2], (Triangle{0, 1, 3}));

  for (bool big : {false, true}) {
    std::string b = ply_header(big ? "binary_big_endian" : "binary_little_endian", props, 4, faces);
    auto put = [&](const void* p, std::size_t n) {
      std::string bytes(static_cast<const char*>(p), n);
      if (big) std::reverse(bytes.begin(), bytes.end());
      b += bytes;
    };
    const double xs[4] = {0, 1, 1, 0};
    const float ys[4] = {0, 0, 1, 1};
    for (int i = 0; i < 4; ++i) {
      float z = 0;
      unsigned char red = 7;
      put(&z, 4), put(&red, 1), put(&xs[i], 8), put(&ys[i], 4);
    }
    unsigned char four = 4;
    put(&four, 1);
    for (int i : {0, 1, 2, 3}) put(&i, 4);
    int six = 6;
    put(&six, 4);
    for (int i : {0, 1, 3, -1, 1, 2}) put(&i, 4);
    TriMesh m = read_ply(b, "b.ply");
    EXPECT_EQ(m.vertices, a.vertices);
    EXPECT_EQ(m.triangles, a.triangles);
    // Truncation anywhere gives an error with a byte offset, never a crash.
    for (std::size_t cut = b.size() - 1; cut > b.size() - 40; --cut)
      EXPECT_THROW(read_ply(b.substr(0, cut), "c.ply"), InputError);
  }
  expect_input_error([&] { read_ply(ply_header("ascii", props, 4000000, faces) + "1 2 3\n", "big.ply"); },
                     "big.ply:4: element 'vertex' declares 4000000 entries");
  expect_input_error([&] { read_ply(ply_header("ascii", props, 4, faces) + "0 255 0 0\n0 1 1 0\n0 2 1 1\n0 3 0 1\n3 0 1 9\n", "i.ply"); },
                     "i.ply:18: face 0 refers to vertex 9 ");
  expect_input_error([] { read_ply("ply\nformat ascii 1.0\nelement vertex 1\n", "h.ply"); }, "no 'end_header'");
}

TEST(MeshIo, OffPolygonsCommentsAndErrors) {
  TriMesh m = read_off("OFF\n# c\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0 # x\n4 0 1 2 3 255 0 0\n", "a.off");
  EXPECT_EQ(m.num_triangles(), 2u);
  m = read_off("COFF 3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n", "b.off");
  EXPECT_EQ(m.num_triangles(), 1u);
  expect_input_error([] { read_off("OFF\n99999999 1 0\n0 0 0\n", "c.off"); }, "c.off:2: OFF header declares 99999999");
  expect_input_error([] { read_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", "d.off"); }, "d.off:6: bad face index '5'");
  expect_input_error([] { read_off("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "e.off"); }, "e.off:6: OFF file ends after 1 of 2 faces");
}

TEST(MeshIo, FormatByContentAndEmptyFiles) {
  EXPECT_EQ(sniff_format("ply\nformat ascii 1.0\n"), MeshFormat::Ply);
  EXPECT_EQ(sniff_format("OFF\n"), MeshFormat::Off);
  EXPECT_EQ(sniff_format("# x\nv 1 2 3\n"), MeshFormat::Obj);
  EXPECT_EQ(sniff_format("solid x\n"), MeshFormat::Stl);
  EXPECT_EQ(format_from_extension("A.PLY"), MeshFormat::Ply);
  expect_input_error([] { read_mesh_from_memory("", "e.stl"); }, "e.stl: empty file");
  expect_input_error([] { read_mesh_from_memory("hello world", "e.txt"); }, "unrecognized mesh format");
  // An OFF file named .stl is read as OFF.
  EXPECT_EQ(read_mesh_from_memory("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "x.stl").num_triangles(), 1u);
  expect_input_error([] { read_mesh("/nonexistent/file.stl"); }, "/nonexistent/file.stl");
}

TEST(MeshIo, WriteReadRoundTrips) {
  TriMesh box = test::make_box({-1.5, 0.25, -3}, {2, 1, 0.125});
  for (MeshFormat f : {MeshFormat::Stl, MeshFormat::Obj, MeshFormat::Ply})
    for (bool ascii : {false, true}) {
      if (ascii && f != MeshFormat::Stl) continue;
      const std::string bytes = write_mesh_to_string(box, f, ascii);
      TriMesh back = read_mesh_from_memory(bytes, std::string("r.") + format_name(f));
      ASSERT_EQ(back.num_triangles(), box.num_triangles()) << format_name(f);
      WeldResult w = weld(back);
      EXPECT_EQ(w.mesh.vertices.size(), 8u);
      for (std::size_t t = 0; t < box.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(back.corner(t, k), box.corner(t, k)) << format_name(f);
    }
  const std::string dir = ::testing::TempDir();
  write_mesh(dir + "/frep_rt.ply", box);
  EXPECT_EQ(read_mesh(dir + "/frep_rt.ply").vertices, box.vertices);
  std::filesystem::remove(dir + "/frep_rt.ply");
  EXPECT_THROW(write_mesh(dir + "/x.off", box), InputError);
}

TEST(Weld, ExactAndToleranceKeepOriginalIndices) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1e-9}, {5, 5, 5}, {-0.0, 0, 0}};
  m.add_triangle(0, 1, 2, 0, 0);
  m.add_triangle(3, 4, 5, 1, 0);
  m.add_triangle(7, 1, 4, 2, 0);
  WeldResult w = weld(m);
  EXPECT_EQ(w.mesh.vertices.size(), 5u);  // 3 == 1, 7 == 0 (-0 == +0); 5 differs by 1e-9; 6 unused
  EXPECT_EQ(w.welded_of_original[3], w.welded_of_original[1]);
  EXPECT_EQ(w.welded_of_original[7], w.welded_of_original[0]);
  EXPECT_EQ(w.welded_of_original[6], kNoVertex);
  EXPECT_EQ(w.original_of_welded[w.welded_of_original[3]], 1u);
  EXPECT_EQ(w.merged, 2u);
  WeldResult t = weld(m, {1e-6});
  EXPECT_EQ(t.mesh.vertices.size(), 4u);
  EXPECT_EQ(t.welded_of_original[5], t.welded_of_original[2]);
  EXPECT_THROW(weld(m, {-1}), InputError);
}

TEST(MeshIo, EveryFileInSharedDataReads) {
  FREP_REQUIRE_SHARED_MESHES();
  for (const auto& entry : std::filesystem::directory_iterator(test::shared_mesh_dir())) {
    if (entry.path().extension() == ".tsv") continue;
    TriMesh m = read_mesh(entry.path().string());
    EXPECT_GT(m.num_triangles(), 0u) << entry.path();
  }
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Regressions from a review of the readers.
TEST(MeshIoRegression, Utf8ByteOrderMarkBeforeTextFormats) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::string stl = bom + "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                "endloop\nendfacet\nendsolid t\n";
  EXPECT_EQ(read_mesh_from_memory(stl, "bom.stl").num_triangles(), 1u);
  EXPECT_EQ(read_mesh_from_memory(bom + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bom.obj").num_triangles(), 1u);
}

TEST(MeshIoRegression, PlyHeaderToleratesTrailingBlanksAndReportsTheRightLine) {
  const std::string head =
      "ply \nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_EQ(read_mesh_from_memory(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "t.ply").num_triangles(), 1u);
  // The NaN is the first value of line 11; the error must say line 11, not the line before.
  const InputError e = expect_input_error(
      [&] { read_mesh_from_memory(head + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "t.ply"); }, "not a finite number");
  EXPECT_EQ(e.line(), 11u);
  // The last value of a line: still that line, not the next one.
  const InputError last = expect_input_error(
      [&] { read_mesh_from_memory(head + "0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n", "t.ply"); }, "not a finite number");
  EXPECT_EQ(last.line(), 10u);
}

TEST(MeshIoRegression, PlyTriangleStripsRestartOnUnsignedMinusOne) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int uint vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 0\n"
      "7 0 1 2 4294967295 1 3 2\n";
  EXPECT_EQ(read_mesh_from_memory(text, "s.ply").num_triangles(), 2u);
}

TEST(MeshIoRegression, StlWriterRefusesWhatSinglePrecisionCannotHoldAndEmptyMeshes) {
  TriMesh big = test::make_box({-1, -1, -1}, {1e300, 1, 1});
  expect_input_error([&] { write_mesh_to_string(big, MeshFormat::Stl, false); }, "single precision");
  EXPECT_NO_THROW(write_mesh_to_string(big, MeshFormat::Obj, false));  // OBJ and PLY keep doubles
  TriMesh empty;
  expect_input_error([&] { write_mesh_to_string(empty, MeshFormat::Ply, false); }, "no triangles");
}

// Variants that other tools write, and mistakes they make, found by generating every variant of
// the formats' specifications: each is read, or refused where the mistake is, or read with a warning.
TEST(MeshIoRegression, FormatVariantsAndMistakesOfOtherTools) {
  const std::string tri_off = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  // OFF: the keyword is optional; ModelNet glues the counts to it; 4OFF is homogeneous; nOFF
  // gives its dimension; plain OFF may put several vertices on a line.
  EXPECT_EQ(read_off("3 1 0\n" + tri_off, "a.off").num_triangles(), 1u);
  EXPECT_EQ(read_off("OFF3 1 0\n" + tri_off, "b.off").num_triangles(), 1u);
  TriMesh h = read_off("4OFF\n3 1 0\n0 0 0 2\n4 0 0 2\n0 6 0 3\n3 0 1 2\n", "c.off");
  EXPECT_EQ(h.vertices[1], (Vec3{2, 0, 0}));
  EXPECT_EQ(h.vertices[2], (Vec3{0, 2, 0}));
  EXPECT_EQ(read_off("nOFF\n3\n3 1 0\n" + tri_off, "d.off").num_triangles(), 1u);
  TriMesh one_line = read_off("OFF\n3 1 0\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n", "e.off");
  EXPECT_EQ(one_line.vertices[2], (Vec3{0, 1, 0}));
  expect_input_error([] { read_off("nOFF 4\n3 1 0\n0 0 0 0\n", "f.off"); }, "f.off:1: OFF variant 'nOFF' of dimension '4'");
  expect_input_error([] { read_off("4OFF\n3 1 0\n0 0 0 0\n1 0 0 1\n0 1 0 1\n3 0 1 2\n", "g.off"); }, "g.off:3: vertex with homogeneous");
  // Old Mac line endings (CR alone), in OBJ and in ASCII PLY.
  EXPECT_EQ(read_obj("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", "h.obj").num_triangles(), 1u);
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string cr = head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  EXPECT_EQ(read_ply(cr, "i.ply").num_triangles(), 1u);
  // OBJ: a vertex line may end in w or a colour, not in anything else.
  EXPECT_EQ(read_obj("v 0 0 0 1 0.5 0.5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "j.obj").num_triangles(), 1u);
  expect_input_error([] { read_obj("v 0 0 0 abc\n", "k.obj"); }, "k.obj:1: unexpected 'abc' after the vertex coordinates");
  // ASCII PLY: one entry per line, so a miscounted line is reported where it is.
  expect_input_error([&] { read_ply(head + "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", "l.ply"); },
                     "l.ply:10: entry of element 'vertex' has more values");
  expect_input_error([&] { read_ply(head + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "m.ply"); },
                     "m.ply:13: PLY data ends early");
  expect_input_error([&] { read_ply(head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "n.ply"); }, "n.ply:13: face 0 has 2 vertex indices");
  expect_input_error([&] { read_ply(head + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", "o.ply"); }, "o.ply:13: integer 300 does not fit");
  std::string v2 = head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  v2.replace(v2.find("1.0"), 3, "2.0");
  expect_input_error([&] { read_ply(v2, "p.ply"); }, "p.ply:2: PLY format version '2.0' is not supported");
  // ASCII STL: a missing 'endsolid' (a file cut between facets) and polygons are read with warnings.
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  TriMesh cut = read_stl("solid t\n" + facet, "q.stl");
  EXPECT_EQ(cut.num_triangles(), 1u);
  ASSERT_EQ(cut.warnings.size(), 1u);
  EXPECT_NE(cut.warnings[0].find("without 'endsolid'"), std::string::npos);
  EXPECT_TRUE(read_stl("solid t\n" + facet + "endsolid t\n", "r.stl").warnings.empty());
}

TEST(MeshIoRegression, DevicesAreNotReadWhole) {
  expect_input_error([] { read_mesh("/dev/zero"); }, "not a regular file");
}

}  // namespace
}  // namespace frep
