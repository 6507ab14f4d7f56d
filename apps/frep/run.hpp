// Runs the command line: parses, calls the chosen subcommand, and turns every outcome into the
// documented exit code and one message on stderr. Separate from main() so tests can drive it.
#pragma once

#include <CLI/CLI.hpp>

namespace frep::cli {

// Exit codes: 0 success, 1 bad input (InputError: a file or value the user gave), 2 bad command
// line, 3 internal error (an InternalError or any other exception: a bug in frep). Commands
// may exit with 4 themselves (frep check: not a solid).
enum ExitCode { kOk = 0, kBadInput = 1, kUsage = 2, kInternal = 3, kNotSolid = 4 };

int run(CLI::App& app, int argc, const char* const* argv);

}  // namespace frep::cli
