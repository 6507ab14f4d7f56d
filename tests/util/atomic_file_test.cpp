// The library's process-wide behaviour around files and child processes: it changes no signal
// disposition and leaves the signal mask as it found it unless the program asks for the cleanup
// handlers (install_interrupt_cleanup); and when the program has asked, a signal in the middle
// of a write removes the temporary file before the process dies as the signal would.
#include "frep/util/atomic_file.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "frep/convert/convert.hpp"
#include "frep/error.hpp"
#include "mesh_test_util.hpp"

namespace frep {
namespace {

namespace fs = std::filesystem;

constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  return out;
}

// What the process does with each of the cleanup signals, and which of them this thread blocks.
struct SignalState {
  std::vector<void (*)(int)> handlers;
  std::vector<bool> blocked;
  bool operator==(const SignalState&) const = default;
};
SignalState signal_state() {
  SignalState s;
  sigset_t mask;
  ::pthread_sigmask(SIG_BLOCK, nullptr, &mask);
  for (int sig : kCleanupSignals) {
    struct sigaction a {};
    ::sigaction(sig, nullptr, &a);
    s.handlers.push_back(a.sa_handler);
    s.blocked.push_back(sigismember(&mask, sig) == 1);
  }
  return s;
}

// This test program never calls install_interrupt_cleanup(): writing files and running TetGen
// (a stand-in that fails at once) must leave every disposition and the mask as they were.
TEST(AtomicFile, TheLibraryTouchesNoSignalsUnlessAsked) {
  const SignalState before = signal_state();
  const fs::path dir = fresh_dir("frep_atomic_signals");
  write_file_atomically((dir / "a.txt").string(), std::string_view("hello\n"));
  write_file_atomically((dir / "b.txt").string(), [&](std::ostream& out) {
    EXPECT_TRUE(signal_state() == before) << "changed while writing";
    out << "world\n";
  });
  EXPECT_EQ(read_file((dir / "a.txt").string()), "hello\n");
  EXPECT_EQ(read_file((dir / "b.txt").string()), "world\n");

  const fs::path script = dir / "failing_tetgen.sh";
  std::ofstream(script) << "#!/bin/sh\necho 'no tetrahedra today'\nexit 3\n";
  fs::permissions(script, fs::perms::owner_all);
  ConvertOptions o;
  o.sign = SignMode::Tetrahedra;
  o.tetgen = script.string();
  try {
    convert_mesh(test::make_box(), o);
    ADD_FAILURE() << "the failing TetGen was not reported";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no tetrahedra today"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(signal_state() == before) << "the library changed a signal's handler or the mask";
  fs::remove_all(dir);
}

// With the handlers the program asked for, SIGTERM in the middle of a write removes the temporary
// file, and the process still dies by SIGTERM. (In a forked child: the handlers are process-wide.
// The "fast" style forks without running the test again, so the child writes into this `dir`.)
TEST(AtomicFileDeathTest, AnInterruptedWriteLeavesNothingWhenTheProgramAsks) {
  GTEST_FLAG_SET(death_test_style, "fast");
  const fs::path dir = fresh_dir("frep_atomic_interrupted");
  const std::string target = (dir / "out.txt").string();
  EXPECT_EXIT(
      {
        std::signal(SIGTERM, SIG_DFL);  // as a program started normally (not ignoring it) has it
        install_interrupt_cleanup();
        write_file_atomically(target, [](std::ostream& out) {
          out << "half a file";
          out.flush();
          std::raise(SIGTERM);
        });
        std::_Exit(0);
      },
      ::testing::KilledBySignal(SIGTERM), "");
  EXPECT_TRUE(names_in(dir).empty()) << "left behind: " << names_in(dir).front();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace frep
