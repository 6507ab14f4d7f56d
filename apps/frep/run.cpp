#include "run.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "frep/error.hpp"

namespace frep::cli {

namespace {

// Command-line mistakes CLI11 reports poorly: no command at all ("A subcommand is required"), an
// unknown command (the same message), and empty arguments (reported later as "<input>").
bool usage_mistake(CLI::App& app, int argc, const char* const* argv) {
  if (argc < 2) {
    std::fputs(app.help().c_str(), stderr);
    std::fprintf(stderr, "frep: error: no command given\n");
    return true;
  }
  const char* first = argv[1];
  const auto subs = app.get_subcommands({});
  const bool known = std::any_of(subs.begin(), subs.end(), [&](CLI::App* sub) { return sub->check_name(first); });
  if (first[0] != '-' && !known) {
    std::string names;
    for (const CLI::App* sub : subs) names += (names.empty() ? "" : ", ") + sub->get_name();
    std::fprintf(stderr, "frep: error: unknown command '%s'; the commands are: %s (frep --help describes them)\n",
                 first, names.c_str());
    return true;
  }
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] == '\0') {
      if (i > 1)
        std::fprintf(stderr, "frep: error: argument %d (after '%s') is empty\n", i, argv[i - 1]);
      else
        std::fprintf(stderr, "frep: error: argument %d is empty\n", i);
      return true;
    }
  return false;
}

}  // namespace

int run(CLI::App& app, int argc, const char* const* argv) {
  if (usage_mistake(app, argc, argv)) return kUsage;
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
