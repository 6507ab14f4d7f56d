// frep: the command-line tool. Argument parsing and calls into the library only.
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "frep/util/atomic_file.hpp"
#include "run.hpp"

int main(int argc, char** argv) {
  CLI::App app{"frep: exact implicit geometry (expressions, evaluation, rendering, meshes)", "frep"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "frep 0.1.0");
  app.footer(
      "Environment: FREP_BACKEND=jit (default: expressions evaluated on many points are compiled to machine code, "
      "AVX-512 or AVX2, with the interpreter's exact results) or interp (the interpreter only); FREP_JIT_DEBUG=1 "
      "reports each compilation on stderr.");
  frep::cli::register_commands(app);
  frep::install_interrupt_cleanup();  // Ctrl-C leaves no temporary file, scratch directory or TetGen behind
  return frep::cli::run(app, argc, argv);
}
