// The library's side of install_interrupt_cleanup (frep/util/atomic_file.hpp): what code that
// makes scratch directories or child processes registers, so that the program's handlers, if the
// program installed them, remove or kill those too. Private to the library (not installed).
#pragma once

#include <string>

namespace frep {

// True once the program has called install_interrupt_cleanup(). Code that would have to hold
// signals back to register something in time (the TetGen runner, around its fork) does so only
// then: without the handlers there is nothing to wait for.
bool interrupt_cleanup_installed();

// Registers a scratch directory (its files, not subdirectories, are removed, then it) and a child
// process group (killed with SIGKILL and reaped) for the handlers; one of each at a time in the
// process. An empty path or a group of 0 clears them. Cheap and harmless without the handlers.
void set_signal_cleanup(const std::string& scratch_dir, int child_group);

}  // namespace frep
