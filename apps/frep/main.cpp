// frep: the command-line tool. Argument parsing and calls into the library only.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "frep/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"frep: exact implicit geometry (expressions, evaluation, rendering)", "frep"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "frep 0.1.0");
  frep::cli::register_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help, version or the usage error
    return rc == 0 ? 0 : 2;
  } catch (const frep::InputError& e) {
    std::fprintf(stderr, "frep: error: %s\n", e.what());
    return 1;
  } catch (const frep::InternalError& e) {
    std::fprintf(stderr, "frep: %s\n", e.what());
    return 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "frep: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "frep: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
