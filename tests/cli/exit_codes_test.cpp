// The command line's exit codes, driven in-process through frep::cli::run with extra commands
// that fail in each way a command can: every outcome maps to its documented code.
#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "frep/error.hpp"
#include "run.hpp"

namespace frep::cli {
namespace {

int run_with(const std::vector<const char*>& args) {
  CLI::App app{"frep (test)", "frep"};
  app.require_subcommand(1);
  register_commands(app);
  app.add_subcommand("throw-input")->callback([] { throw InputError("in.vm", 3, "bad token"); });
  app.add_subcommand("throw-internal")->callback([] { FREP_ASSERT(1 + 1 == 3, "arithmetic"); });
  app.add_subcommand("throw-std")->callback([] { throw std::out_of_range("vector::at"); });
  app.add_subcommand("throw-other")->callback([] { throw 42; });
  app.add_subcommand("throw-bad-alloc")->callback([] { throw std::bad_alloc(); });
  app.add_subcommand("ok")->callback([] {});
  std::vector<const char*> argv = {"frep"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run(app, static_cast<int>(argv.size()), argv.data());
}

TEST(ExitCodes, EveryOutcomeHasItsCode) {
  EXPECT_EQ(run_with({"ok"}), kOk);
  EXPECT_EQ(run_with({"--help"}), kOk);
  EXPECT_EQ(run_with({"throw-input"}), kBadInput);
  EXPECT_EQ(run_with({"throw-bad-alloc"}), kBadInput);
  EXPECT_EQ(run_with({}), kUsage);
  EXPECT_EQ(run_with({"no-such-command"}), kUsage);
  EXPECT_EQ(run_with({"info"}), kUsage);  // missing argument
  // Anything that is neither an input error nor a usage error is a bug: exit 3, never 1.
  EXPECT_EQ(run_with({"throw-internal"}), kInternal);
  EXPECT_EQ(run_with({"throw-std"}), kInternal);
  EXPECT_EQ(run_with({"throw-other"}), kInternal);
}

TEST(ExitCodes, CommandLineMistakesAreNamed) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(run_with({"rendr", "x.vm"}), kUsage);
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("unknown command 'rendr'"), std::string::npos) << err;
  EXPECT_NE(err.find("render"), std::string::npos) << err;

  testing::internal::CaptureStderr();
  EXPECT_EQ(run_with({"info", ""}), kUsage);
  err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("argument 2 (after 'info') is empty"), std::string::npos) << err;

  testing::internal::CaptureStderr();
  EXPECT_EQ(run_with({}), kUsage);
  err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("no command given"), std::string::npos) << err;
  EXPECT_NE(err.find("Subcommands"), std::string::npos) << err;  // the help, listing them
}

}  // namespace
}  // namespace frep::cli
