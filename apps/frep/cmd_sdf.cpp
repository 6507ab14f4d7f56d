#include "commands.hpp"

namespace frep::cli {
void register_sdf(CLI::App&) {}
}  // namespace frep::cli
