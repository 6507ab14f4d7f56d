// Outputs to a device: the README says a device such as /dev/null is written in place. Commands
// that choose the output format from the extension take a device's name without one and write
// their default format to it (render PNG, mesh / offset / shell / repair binary STL, convert
// .frep, sample .npy), instead of refusing the name as an unknown format.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "frep/util/atomic_file.hpp"
#include "cli_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

const std::string kBracket = test::shell_quote(FREP_SOURCE_DIR "/examples/bracket.obj");

TEST(DeviceOutputCli, EveryCommandThatChoosesAFormatWritesToDevNull) {
  test::ScratchDir dir;
  // A 2D expression of our own for the pictures and samples.
  test::write_text(dir.path("disc.vm"), "_0 var-x\n_1 var-y\n_2 square _0\n_3 square _1\n_4 add _2 _3\n_5 sqrt _4\n"
                                        "_6 const 0.5\n_7 sub _5 _6\n");
  const std::string disc = test::shell_quote(dir.path("disc.vm"));
  struct stat before {};
  ASSERT_EQ(::stat("/dev/null", &before), 0);
  for (const std::string& args : {
           "render " + disc + " --size 32",
           "render " + kBracket + " --3d --size 32",
           "mesh " + kBracket + " -r 12",
           "convert " + kBracket,
           "offset " + kBracket + " 0.1 -r 12",
           "shell " + kBracket + " 0.1 -r 12",
           "sample " + disc + " --grid 4",
           "sample " + kBracket + " --points 100",
           "repair " + kBracket,
       }) {
    const test::CliRun r = test::run_frep(dir, args + " -o /dev/null");
    EXPECT_EQ(r.code, 0) << "frep " << args << " -o /dev/null\n" << r.err;
    EXPECT_NE(r.out.find("wrote /dev/null"), std::string::npos) << "frep " << args << ":\n" << r.out;
  }
  // Written in place: /dev/null is still the same character device, not a file renamed over it.
  struct stat after {};
  ASSERT_EQ(::stat("/dev/null", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode));
  EXPECT_EQ(after.st_rdev, before.st_rdev);
  // Nothing but the command's log was left in the scratch directory (no temporary file).
  for (const auto& e : fs::directory_iterator(dir.dir()))
    EXPECT_TRUE(e.path().filename() == "log" || e.path().filename() == "disc.vm") << e.path();
}

TEST(DeviceOutputCli, AnUnknownExtensionOnAFileIsStillRefused) {
  test::ScratchDir dir;
  for (const char* name : {"render", "mesh", "convert", "offset", "shell", "sample"}) {
    const std::string cmd = name;
    std::string args = cmd + " " + kBracket + " -o " + test::shell_quote(dir.path("out.xyz"));
    if (cmd == "offset" || cmd == "shell") args = cmd + " " + kBracket + " 0.1 -o " + test::shell_quote(dir.path("out.xyz"));
    if (cmd == "render") args += " --3d";
    if (cmd == "mesh") args += " -r 8";
    if (cmd == "sample") args += " --grid 4";
    const test::CliRun r = test::run_frep(dir, args);
    EXPECT_NE(r.code, 0) << "frep " << args;
    EXPECT_FALSE(fs::exists(dir.path("out.xyz"))) << "frep " << args;
  }
}

TEST(DeviceOutput, IsDeviceIsTrueForCharacterDevicesOnly) {
  test::ScratchDir dir;
  test::write_text(dir.path("file.txt"), "x");
  EXPECT_TRUE(is_device("/dev/null"));
  EXPECT_FALSE(is_device(dir.path("file.txt")));
  EXPECT_FALSE(is_device(dir.path("missing")));
  EXPECT_FALSE(is_device(dir.dir().string()));
}

}  // namespace
}  // namespace frep
