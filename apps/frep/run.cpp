#include "run.hpp"

#include <cstdio>
#include <exception>
#include <new>

#include "frep/error.hpp"

namespace frep::cli {

int run(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help, version or the usage error
    return rc == 0 ? kOk : kUsage;
  } catch (const InputError& e) {
    std::fprintf(stderr, "frep: error: %s\n", e.what());
    return kBadInput;
  } catch (const InternalError& e) {
    std::fprintf(stderr, "frep: %s\nThis is a bug in frep; please report it.\n", e.what());
    return kInternal;
  } catch (const std::bad_alloc&) {
    // Not the input's fault as such, and not a bug: the job needs more memory than there is.
    std::fprintf(stderr, "frep: error: out of memory\n");
    return kBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "frep: internal error: %s\nThis is a bug in frep; please report it.\n", e.what());
    return kInternal;
  } catch (...) {
    std::fprintf(stderr, "frep: internal error: unknown exception\nThis is a bug in frep; please report it.\n");
    return kInternal;
  }
  return kOk;
}

}  // namespace frep::cli
