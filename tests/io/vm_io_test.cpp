// Fidget's .vm text format: every shared model loads and round-trips bit for bit; recip is
// written as div by 1; every kind of error names the file and the right line.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/script/rhai.hpp"
#include "frep/io/vm.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/script/save.hpp"
#include "frep/io/vm.hpp"
#include "frep/util/atomic_file.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;
using test::fstr;
using test::same_value;

std::string to_vm(const Graph& g, NodeId root) {
  std::ostringstream os;
  write_vm(os, g, root);
  return os.str();
}

// Values at random points inside [-1.5, 1.5]^3 (z = 0 for 2D models) plus a few odd points.
void expect_same_values(const Tape& a, const Tape& b, bool three_d, std::mt19937_64& rng, const std::string& what) {
  PointEvaluator pe;
  for (int i = 0; i < 300; ++i) {
    float x = std::uniform_real_distribution<float>(-1.5f, 1.5f)(rng);
    float y = std::uniform_real_distribution<float>(-1.5f, 1.5f)(rng);
    float z = three_d ? std::uniform_real_distribution<float>(-1.5f, 1.5f)(rng) : 0.0f;
    if (i < 20) x = test::random_float(rng), y = test::random_float(rng), z = three_d ? test::random_float(rng) : 0.0f;
    const float va = pe.eval(a, x, y, z), vb = pe.eval(b, x, y, z);
    ASSERT_TRUE(same_value(va, vb)) << what << " at (" << fstr(x) << ", " << fstr(y) << ", " << fstr(z) << "): "
                                    << fstr(va) << " vs " << fstr(vb);
  }
}

TEST(VmFiles, EverySharedModelLoadsAndRoundTrips) {
  if (!fs::is_directory(test::data_dir())) GTEST_SKIP() << "shared test data not found: " << test::data_dir();
  std::mt19937_64 rng(61);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(test::data_dir())) {
    if (entry.path().extension() != ".vm") continue;
    ++files;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    const Model m = read_vm(path);
    ASSERT_NE(m.root, kNoNode);
    const Tape t = Tape::compile(*m.graph, m.root);
    const bool three_d = (t.vars_used() & 4) != 0;
    // Direct graph evaluation agrees with the tape.
    for (int i = 0; i < 20; ++i) {
      const float x = std::uniform_real_distribution<float>(-1, 1)(rng), y = std::uniform_real_distribution<float>(-1, 1)(rng);
      const float z = three_d ? std::uniform_real_distribution<float>(-1, 1)(rng) : 0.0f;
      PointEvaluator pe;
      ASSERT_TRUE(same_value(pe.eval(t, x, y, z), test::eval_graph<float>(*m.graph, m.root, x, y, z)));
    }
    const std::string text = to_vm(*m.graph, m.root);
    EXPECT_EQ(text.find("recip"), std::string::npos);
    const Model again = parse_vm(text, path + " (written)");
    const Tape t2 = Tape::compile(*again.graph, again.root);
    EXPECT_EQ(t2.size(), t.size());
    expect_same_values(t, t2, three_d, rng, path);
    // Writing is stable: the re-read model prints the same text.
    EXPECT_EQ(to_vm(*again.graph, again.root), text);
    // load_expression reads .vm too.
    const Model via_load = load_expression(path);
    EXPECT_EQ(Tape::compile(*via_load.graph, via_load.root).size(), t.size());
  }
  EXPECT_GE(files, 5);
}

TEST(VmFiles, ProsperoShape) {
  FREP_REQUIRE_DATA("prospero.vm");
  const Model m = read_vm(test::data_file("prospero.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  EXPECT_EQ(t.vars_used(), 3);  // x and y
  EXPECT_GT(t.size(), 7000u);
  EXPECT_LE(t.size(), 7866u);
}

TEST(VmWrite, RecipIsWrittenAsDivByOne) {
  Graph g;
  auto x = g.x(), y = g.y();
  const NodeId root = (recip(x) + recip(y * 2.0f) - 1.0f / (x - y)).id();
  const std::string text = to_vm(g, root);
  EXPECT_EQ(text.find("recip"), std::string::npos) << text;
  EXPECT_NE(text.find("div"), std::string::npos);
  const Model m = parse_vm(text);
  std::mt19937_64 rng(62);
  expect_same_values(Tape::compile(g, root), Tape::compile(*m.graph, m.root), false, rng, "recip");
  // The reader accepts frep's own `recip` token as well.
  const Model r = parse_vm("a var-x\nb recip a\n");
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(Tape::compile(*r.graph, r.root), 4, 0, 0), 0.25f);
  EXPECT_EQ(pe.eval(Tape::compile(*r.graph, r.root), -0.0f, 0, 0), -std::numeric_limits<float>::infinity());
}

TEST(VmWrite, EveryOpcodeAndSpecialConstantRoundTripsExactly) {
  Graph g;
  std::mt19937_64 rng(63);
  test::GenOptions opt;
  opt.special_const_prob = 0.3;
  opt.max_depth = 7;
  test::ExprGen gen(g, rng, opt);
  std::vector<NodeId> roots;
  for (int i = 0; i < 40; ++i) roots.push_back(gen.gen());
  for (float c : test::special_floats()) {
    const NodeId k = g.constant(c);
    roots.push_back(g.binary(Op::Add, g.binary(Op::Mul, g.var_x(), k), g.var_y()));
    roots.push_back(k);  // a constant root
  }
  for (NodeId root : roots) {
    const Model m = parse_vm(to_vm(g, root), "roundtrip.vm");
    expect_same_values(Tape::compile(g, root), Tape::compile(*m.graph, m.root), true, rng, "round trip");
    if (g.is_const(root)) {
      ASSERT_TRUE(m.graph->is_const(m.root));
      EXPECT_TRUE(same_value(m.graph->node(m.root).value, g.node(root).value));
      if (!std::isnan(g.node(root).value)) {
        EXPECT_TRUE(test::same_bits(m.graph->node(m.root).value, g.node(root).value));
      }
    }
  }
}

TEST(VmWrite, SaveIsAtomicAndFailsCleanly) {
  const fs::path dir = fs::temp_directory_path() / ("frep_vm_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Graph g;
  const NodeId root = (g.x() * g.y() - 1.0f).id();
  const std::string ok = (dir / "out.vm").string();
  save_vm(ok, g, root);
  const Model m = read_vm(ok);
  EXPECT_EQ(Tape::compile(*m.graph, m.root).size(), Tape::compile(g, root).size());
  const std::string bad = (dir / "no_such_dir" / "out.vm").string();
  EXPECT_THROW(save_vm(bad, g, root), InputError);
  EXPECT_FALSE(fs::exists(bad));
  EXPECT_THROW(save_vm(dir.string(), g, root), InputError);  // a directory
  int leftovers = 0;
  for (const auto& e : fs::directory_iterator(dir)) leftovers += e.path().filename() != "out.vm";
  EXPECT_EQ(leftovers, 0) << "temporary files left behind";
  fs::remove_all(dir);
}

// Writing through a symbolic link replaces the file it names and keeps the link; a device such as
// /dev/null is written in place, never replaced by a regular file; a replaced file keeps its mode.
TEST(AtomicWrite, FollowsLinksWritesDevicesInPlaceAndKeepsModes) {
  const fs::path dir = fs::temp_directory_path() / ("frep_atomic_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path target = dir / "target.txt", link = dir / "link.txt", dangling = dir / "dangling.txt";
  { std::ofstream(target) << "old"; }
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink("target.txt", link);
  fs::create_symlink("made.txt", dangling);
  write_file_atomically(link.string(), std::string_view("new"));
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read_file(target.string()), "new");
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_file_atomically(dangling.string(), std::string_view("made"));
  EXPECT_TRUE(fs::is_symlink(dangling));
  EXPECT_EQ(read_file((dir / "made.txt").string()), "made");
  EXPECT_NO_THROW(write_file_atomically("/dev/null", std::string_view("nothing")));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A name of 255 bytes, the most a file name may have: the temporary name is cut to fit.
  const fs::path longest = dir / std::string(255, 'n');
  EXPECT_NO_THROW(write_file_atomically(longest.string(), std::string_view("long")));
  EXPECT_EQ(read_file(longest.string()), "long");
  const auto entries = std::distance(fs::directory_iterator(dir), fs::directory_iterator());
  EXPECT_EQ(entries, 5) << "temporary files left behind";
  fs::remove_all(dir);
}

// What is known of a field (FieldInfo: its Lipschitz bound and the box of its inside) survives
// every expression format: leading comments in .vm and .rhai (which Fidget ignores), the header
// of .frep.
TEST(ExpressionFiles, FieldInfoRoundTrips) {
  const fs::path dir = fs::temp_directory_path() / ("frep_field_info_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Model m;
  m.root = (sqrt(square(m.graph->x()) + square(m.graph->y()) + square(m.graph->z())) - 0.5f).id();
  const Box3 box{{-0.1, -2.5e-7, 3}, {0.30000000000000004, 1e300, 3}};
  for (double l : {0.0, 1.0, 2.5})
    for (bool bounded : {false, true})
      for (const char* ext : {".vm", ".rhai", ".frep"}) {
        m.info.lipschitz = l;
        m.info.bounds = bounded ? box : Box3{};
        const std::string path = (dir / (std::string("m") + ext)).string();
        save_expression(path, m);
        const FieldInfo got = load_expression(path).info;
        EXPECT_EQ(got.lipschitz, l) << ext << ", L = " << l;
        EXPECT_EQ(got.bounds.empty(), !bounded) << ext;
        if (bounded)
          for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(got.bounds.lo[a], box.lo[a]) << ext << " axis " << a;
            EXPECT_EQ(got.bounds.hi[a], box.hi[a]) << ext << " axis " << a;
          }
      }
  fs::remove_all(dir);
  EXPECT_EQ(parse_vm("# frep: lipschitz 1 (a distance)\n_0 var-x\n", "a.vm").info.lipschitz, 1.0);
  EXPECT_EQ(parse_vm("\n  #   frep: lipschitz 0.5\n# other\n_0 var-x\n", "a.vm").info.lipschitz, 0.5);
  EXPECT_EQ(parse_vm("# frep: bounds 0 1 2 3 4 5\n_0 var-x\n", "a.vm").info.bounds.hi.z, 5.0);
  EXPECT_EQ(parse_vm("# frep: someday 1\n_0 var-x\n", "a.vm").info.lipschitz, 0.0);  // unknown facts are ignored
  // Only leading comments count; other comments mentioning it are ignored.
  EXPECT_EQ(parse_vm("_0 var-x\n# frep: lipschitz 1\n", "a.vm").info.lipschitz, 0.0);
  EXPECT_EQ(parse_vm("# frep lipschitz 1\n_0 var-x\n", "a.vm").info.lipschitz, 0.0);
  for (const char* bad : {"# frep: lipschitz\n_0 var-x\n", "# frep: lipschitz -1\n_0 var-x\n",
                          "\n# frep: lipschitz nan\n_0 var-x\n", "# frep: lipschitz 1x\n_0 var-x\n",
                          "# frep: bounds 0 0 0 1 1\n_0 var-x\n", "# frep: bounds 0 0 0 1 inf 1\n_0 var-x\n",
                          "# frep: bounds 2 0 0 1 1 1\n_0 var-x\n"}) {
    try {
      parse_vm(bad, "bad.vm");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.vm");
      EXPECT_GE(e.line(), 1u);
      EXPECT_NE(std::string(e.what()).find("frep: "), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(parse_rhai("// frep: lipschitz 1\nx", "a.rhai").info.lipschitz, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Syntax accepted

TEST(VmParse, IdsCommentsBlankLinesCrlfTabsAndForwardReferences) {
  PointEvaluator pe;
  auto value = [&](const std::string& text, float x, float y, float z = 0) {
    const Model m = parse_vm(text, "t.vm");
    return pe.eval(Tape::compile(*m.graph, m.root), x, y, z);
  };
  EXPECT_EQ(value("# header\n\nfoo var-x\n  bar\tvar-y   # trailing comment\n\n#x\nbaz add foo bar\n", 1, 2), 3.0f);
  EXPECT_EQ(value("a var-x\r\nb const 2.5\r\nc mul a b\r\n", 2, 0), 5.0f);
  EXPECT_EQ(value("a var-x\r\nb const 2.5\r\nc mul a b", 2, 0), 5.0f) << "no final newline";
  EXPECT_EQ(value("1 var-x\n2 var-y\n3 sub 1 2\n", 5, 3), 2.0f) << "numeric ids";
  EXPECT_EQ(value("x.y!@$ var-x\n_ var-z\nroot-node max x.y!@$ _\n", 1, 0, 4), 4.0f) << "any token is an id";
  EXPECT_EQ(value("const var-x\nadd const 1\nv add const add\n", 2, 0), 3.0f) << "opcode names as ids";
  // Forward references: the root is the last line, other lines may use ids defined later.
  EXPECT_EQ(value("a sub b c\nb var-x\nc var-y\nr neg a\n", 5, 3), -2.0f);
  EXPECT_EQ(value("q square b\nb var-y\nr neg q\n", 0, 3), -9.0f);
  EXPECT_EQ(value("s sin t\nt cos u\nu var-x\nr min s u\n", 0.5f, 0), 0.5f);
  // The last line is the root even if earlier lines are unused.
  EXPECT_EQ(value("a var-x\nb var-y\nunused add a b\nr var-y\n", 5, 3), 3.0f);
  // Numbers: exponents, signs, overflow to infinity, negative zero, nan.
  EXPECT_EQ(value("c const 1e40\n", 0, 0), std::numeric_limits<float>::infinity());
  EXPECT_EQ(value("c const -1E+2\n", 0, 0), -100.0f);
  EXPECT_TRUE(test::same_bits(value("c const -0\n", 0, 0), -0.0f));
  EXPECT_TRUE(std::isnan(value("c const nan\n", 0, 0)));
  EXPECT_EQ(value("c const 1e-45\n", 0, 0), std::numeric_limits<float>::denorm_min());
}

// Regression: lines out of order whose argument was queued by a sibling used to be reported as a
// cycle. Only a node on the current depth-first path makes a cycle.
TEST(VmParseRegression, OutOfOrderSharedArgumentIsNotACycle) {
  PointEvaluator pe;
  const Model m = parse_vm("r add q p\nq neg p\np var-x\nout mul r r\n", "dag.vm");
  EXPECT_EQ(pe.eval(Tape::compile(*m.graph, m.root), 2, 0, 0), 0.0f);
  const Model m2 = parse_vm("r mul a b\na neg b\nb var-x\nout neg r\n", "dag2.vm");
  EXPECT_EQ(pe.eval(Tape::compile(*m2.graph, m2.root), 3, 0, 0), 9.0f);
}

// The same file in order parses fine (control for the test above).
TEST(VmParse, InOrderSharedArgument) {
  PointEvaluator pe;
  const Model m = parse_vm("p var-x\nq neg p\nr add q p\nout mul r r\n", "dag.vm");
  EXPECT_EQ(pe.eval(Tape::compile(*m.graph, m.root), 2, 0, 0), 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Errors: InputError with the file name and the line of the offending instruction.

struct ErrorCase {
  std::string name;
  std::string text;
  std::uint64_t line;    // expected line (0 = no specific line)
  std::string mention;   // a word the message must contain
};

void expect_error(const ErrorCase& c) {
  SCOPED_TRACE(c.name);
  try {
    parse_vm(c.text, "bad.vm");
    ADD_FAILURE() << "no error for " << c.name;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "bad.vm");
    EXPECT_EQ(e.line(), c.line) << what;
    EXPECT_NE(what.find("bad.vm"), std::string::npos) << what;
    if (c.line > 0) {
      EXPECT_NE(what.find("bad.vm:" + std::to_string(c.line)), std::string::npos) << what;
    }
    EXPECT_NE(what.find(c.mention), std::string::npos) << what << " (expected to mention '" << c.mention << "')";
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

TEST(VmParseErrors, EveryKindNamesTheFileAndLine) {
  const std::vector<ErrorCase> cases = {
      {"unknown opcode", "a var-x\n# c\nb frobnicate a\n", 3, "frobnicate"},
      {"unknown opcode recip-like", "a var-x\nb reciprocal a\n", 2, "reciprocal"},
      {"too few args", "a var-x\n\n\nb add a\n", 4, "add"},
      {"too many args", "a var-x\nb neg a a\n", 2, "neg"},
      {"leaf with args", "a var-x 3\n", 1, "var-x"},
      {"only an id", "a var-x\nlonely\n", 2, "lonely"},
      {"undefined id", "a var-x\nb var-y\nc add a zz\n", 3, "zz"},
      {"duplicate id", "a var-x\nb var-y\na var-z\nc add a b\n", 3, "a"},
      {"bad number 1.2.3", "a const 1.2.3\n", 1, "1.2.3"},
      {"bad number abc", "x var-x\na const abc\n", 2, "abc"},
      {"bad number 1,5", "a const 1,5\n", 1, "1,5"},
      {"empty number", "x var-x\na const\n", 2, "const"},
      {"two cycle", "a neg b\nb neg a\n", 0, "cycle"},
      {"self reference", "x var-x\na add a x\n", 2, "cycle"},
      {"long cycle", "x var-x\na add x c\nb neg a\nc sin b\n", 0, "cycle"},
      {"crlf line numbers", "a var-x\r\n\r\nb bogus a\r\n", 3, "bogus"},
  };
  for (const ErrorCase& c : cases) {
    if (c.line == 0) {
      // Cycles: any line that is part of the cycle is acceptable.
      try {
        parse_vm(c.text, "bad.vm");
        ADD_FAILURE() << "no error for " << c.name;
      } catch (const InputError& e) {
        EXPECT_GE(e.line(), 1u) << c.name;
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bad.vm:" + std::to_string(e.line())), std::string::npos) << e.what();
      }
    } else {
      expect_error(c);
    }
  }
}

TEST(VmParseErrors, DuplicateIdMentionsTheFirstDefinition) {
  try {
    parse_vm("a var-x\nb var-y\na var-z\n", "dup.vm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3u);
    EXPECT_NE(e.detail().find("line 1"), std::string::npos) << e.what();
  }
}

TEST(VmParseErrors, EmptyAndCommentOnlyInput) {
  for (const std::string& text : {std::string(""), std::string("\n\n"), std::string("# only\n# comments\n\n   \n"),
                                 std::string("\r\n\t\n")}) {
    try {
      parse_vm(text, "empty.vm");
      ADD_FAILURE() << "no error for empty input";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "empty.vm");
      EXPECT_NE(std::string(e.what()).find("empty.vm"), std::string::npos);
    }
  }
}

TEST(VmParseErrors, MissingFileAndDirectory) {
  const std::string missing = "/nonexistent/dir/model.vm";
  try {
    read_vm(missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  EXPECT_THROW(load_expression(missing), InputError);
  EXPECT_THROW(read_vm(fs::temp_directory_path().string()), InputError);
}

TEST(VmParseErrors, ErrorInAFileOnDiskHasItsPathAndLine) {
  const fs::path p = fs::temp_directory_path() / ("frep_bad_" + std::to_string(::getpid()) + ".vm");
  {
    std::ofstream out(p);
    out << "# comment\nx var-x\ny var-y\n\nz mul x w\n";
  }
  try {
    read_vm(p.string());
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 5u);
    EXPECT_NE(std::string(e.what()).find(p.string() + ":5"), std::string::npos) << e.what();
  }
  fs::remove(p);
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// A UTF-8 byte order mark (some Windows editors write one) is skipped by both text formats,
// with or without an extension that says which format it is.
TEST(TextFormats, ByteOrderMarkIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  const Model vm = parse_vm(bom + "# frep: lipschitz 1\n_0 var-x\n_1 const 2\n_2 sub _0 _1\n", "bom.vm");
  EXPECT_EQ(vm.info.lipschitz, 1.0);
  const Model rhai = parse_rhai(bom + "// frep: lipschitz 1\nx - 2\n", "bom.rhai");
  EXPECT_EQ(rhai.info.lipschitz, 1.0);
  for (const Model* m : {&vm, &rhai}) {
    const Tape t = Tape::compile(*m->graph, m->root);
    PointEvaluator pe;
    EXPECT_EQ(pe.eval(t, 5, 0, 0), 3.0f);
  }
  const std::string dir = ::testing::TempDir();
  const std::string path = dir + "/frep_bom_expression";
  { std::ofstream(path, std::ios::binary) << bom << "_0 var-x\n_1 const 2\n_2 sub _0 _1\n"; }
  const Model loaded = load_expression(path);
  PointEvaluator pe;
  EXPECT_EQ(pe.eval(Tape::compile(*loaded.graph, loaded.root), 5, 0, 0), 3.0f);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace frep
