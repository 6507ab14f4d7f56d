// `frep render --3d` and `--slice` end to end: the PNG written is the library's picture, and bad
// command lines (slice syntax, view names, options without their mode, bounds) exit 2 with a
// message naming the option, while a colour picture asked for as .pgm exits 1.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "frep/render/render3d.hpp"
#include "frep/render/shade.hpp"
#include "frep/render/slice.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("frep_render_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    auto x = g_.x(), y = g_.y(), z = g_.z();
    root_ = min(sqrt(square(x - 0.2f) + square(y) + square(z)) - 0.5f, max(abs(x + 0.4f) - 0.3f, abs(y) - 0.6f)).id();
    model_ = path("m.vm");
    save_vm(model_, g_, root_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string err() const {
    std::ifstream in(path("err.txt"));
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  int run(const std::string& args) {
    const std::string cmd = std::string(FREP_CLI_PATH) + " render '" + model_ + "' " + args + " > '" + path("out.txt") +
                            "' 2> '" + path("err.txt") + "'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // The PNG's pixels, or empty if it cannot be read.
  Image load(const std::string& name) {
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path(name).c_str(), &w, &h, &n, 0);
    Image img;
    if (!data) return img;
    img.width = w;
    img.height = h;
    img.channels = n;
    img.pixels.assign(data, data + static_cast<std::size_t>(w) * h * n);
    stbi_image_free(data);
    return img;
  }
  Tape tape() const { return Tape::compile(g_, root_); }

  fs::path dir_;
  Graph g_;
  NodeId root_ = kNoNode;
  std::string model_;
};

TEST_F(RenderCli, ThreeDModesWriteTheLibrarysPictures) {
  ASSERT_EQ(run("--3d --size 40 -j 2 -o '" + path("a.png") + "'"), 0) << err();
  Render3DOptions o;
  o.size = 40;
  const DepthMap map = render3d(tape(), o);
  EXPECT_EQ(load("a.png").pixels, shade(map).pixels);
  EXPECT_EQ(load("a.png").channels, 3);

  ASSERT_EQ(run("--3d --size 40 --view top --rotate 10,-5 --mode normals -o '" + path("n.png") + "'"), 0) << err();
  o.view = ViewDirection::Top;
  o.yaw = 10;
  o.pitch = -5;
  ShadeOptions so;
  so.mode = ShadeMode::Normals;
  EXPECT_EQ(load("n.png").pixels, shade(render3d(tape(), o), so).pixels);

  ASSERT_EQ(run("--3d --size 30 --view front --mode depth --bounds -1,-1,-0.5,1,1,0.5 -o '" + path("d.pgm") + "'"), 0)
      << err();
  ASSERT_EQ(run("--3d --size 30 --view front --mode depth --ao --bounds -1,-1,-0.5,1,1,0.5 -o '" + path("d.png") + "'"), 0)
      << err();
  const Image depth = load("d.png");
  EXPECT_EQ(depth.channels, 1);
  Render3DOptions d;
  d.size = 30;
  d.view = ViewDirection::Front;
  d.bounds = Box3{{-1, -1, -0.5}, {1, 1, 0.5}};
  so.mode = ShadeMode::Depth;
  EXPECT_EQ(depth.pixels, shade(render3d(tape(), d), so).pixels);

  ASSERT_EQ(run("--3d --size 30 --up z --view front -o '" + path("z.png") + "'"), 0) << err();
  Render3DOptions zo;
  zo.size = 30;
  zo.view = ViewDirection::Front;
  zo.z_up = true;
  EXPECT_EQ(load("z.png").pixels, shade(render3d(tape(), zo)).pixels);

  ASSERT_EQ(run("--3d --size 30 --ao -o '" + path("ao.png") + "'"), 0) << err();
  EXPECT_NE(load("ao.png").pixels, load("a.png").pixels);
}

TEST_F(RenderCli, SlicesWriteTheLibrarysPictures) {
  ASSERT_EQ(run("--slice y=0.1 --size 50 --contour 0.25 -o '" + path("s.png") + "'"), 0) << err();
  SliceOptions o;
  o.size = 50;
  o.axis = 1;
  o.offset = 0.1f;
  o.contour = 0.25;
  EXPECT_EQ(load("s.png").pixels, render_slice(tape(), o).pixels);
  ASSERT_EQ(run("--slice X=-0.25 --size 20 --bounds 0,-1,-2,1,1,2 -o '" + path("x.png") + "'"), 0) << err();
  const Image x = load("x.png");
  EXPECT_EQ(x.height, 20);
  EXPECT_EQ(x.width, 10) << "y spans 2, z spans 4";
}

TEST_F(RenderCli, BadCommandLines) {
  const std::string out = " -o '" + path("o.png") + "'";
  for (const char* bad : {"--slice w=1", "--slice z", "--slice z=", "--slice z=abc", "--slice z=nan", "--slice 0.3",
                          "--slice z=1e99"}) {
    EXPECT_EQ(run(std::string(bad) + out), 2) << bad;
    EXPECT_NE(err().find("AXIS=VALUE"), std::string::npos) << bad << ": " << err();
  }
  EXPECT_EQ(run("--3d --view sideways" + out), 2);
  EXPECT_NE(err().find("--view"), std::string::npos) << err();
  EXPECT_EQ(run("--3d --mode fancy" + out), 2);
  EXPECT_EQ(run("--3d --up x" + out), 2);
  EXPECT_EQ(run("--up z" + out), 2) << "--up needs --3d";
  EXPECT_EQ(run("--view front" + out), 2) << "--view needs --3d";
  EXPECT_NE(err().find("--3d"), std::string::npos) << err();
  EXPECT_EQ(run("--ao" + out), 2);
  EXPECT_EQ(run("--3d --slice z=0" + out), 2);
  EXPECT_EQ(run("--3d --z 0.5" + out), 2);
  EXPECT_EQ(run("--contour 0.1" + out), 2) << "--contour needs --slice";
  EXPECT_EQ(run("--slice z=0 --contour -1" + out), 2);
  EXPECT_EQ(run("--slice z=0 --contour 0" + out), 2);
  EXPECT_EQ(run("--3d --rotate 10" + out), 2);
  EXPECT_EQ(run("--3d --bounds 1,0,0,0,1,1" + out), 2);
  EXPECT_NE(err().find("empty along x"), std::string::npos) << err();
  EXPECT_EQ(run("--3d --bounds 0,0,0,1,1" + out), 2);
  EXPECT_EQ(run("--bounds -1,-1,-1,1,1,1" + out), 2) << "--bounds needs --3d or --slice";
  EXPECT_FALSE(fs::exists(path("o.png")));
  // A colour picture cannot be a PGM: bad input, before any rendering.
  EXPECT_EQ(run("--3d -o '" + path("c.pgm") + "'"), 1);
  EXPECT_NE(err().find("grayscale"), std::string::npos) << err();
  EXPECT_EQ(run("--slice z=0 -o '" + path("c.pgm") + "'"), 1);
}

}  // namespace
}  // namespace frep
