// Each subcommand lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

namespace frep::cli {

void register_info(CLI::App& app);
void register_eval(CLI::App& app);
void register_render(CLI::App& app);

inline void register_commands(CLI::App& app) {
  register_info(app);
  register_eval(app);
  register_render(app);
}

}  // namespace frep::cli
