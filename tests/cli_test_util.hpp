// Shared helpers for tests that run the `frep` program as a user would: a scratch directory
// named after the running test, shell quoting, whole-file reads and writes, and one call that
// runs `frep` with its exit code, stdout and stderr captured.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace frep::test {

namespace fs = std::filesystem;

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

// A directory under the system temp dir, named after the running test, removed afterwards.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("frep_test_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~ScratchDir() { fs::remove_all(dir_); }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

// What a run of the `frep` program gave.
struct CliRun {
  int code = -1;  // exit code; -1 if it did not exit normally
  std::string out, err;
};

// Runs `frep ARGS` (ARGS as a shell would split them) with `stdin_text` as its input. Its
// stdout and stderr go through files in `scratch`'s subdirectory "log", so that a test listing
// the scratch directory sees only what the command wrote.
inline CliRun run_frep(const ScratchDir& scratch, const std::string& args, const std::string& stdin_text = "") {
  const fs::path log = scratch.dir() / "log";
  fs::create_directories(log);
  const std::string in = (log / "stdin.txt").string(), out = (log / "stdout.txt").string(),
                    err = (log / "stderr.txt").string();
  write_text(in, stdin_text);
  const std::string cmd = shell_quote(FREP_CLI_PATH) + " " + args + " <" + shell_quote(in) + " >" + shell_quote(out) +
                          " 2>" + shell_quote(err);
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

}  // namespace frep::test
