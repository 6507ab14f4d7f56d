// Each subcommand lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

namespace frep::cli {

void register_info(CLI::App& app);
void register_eval(CLI::App& app);
void register_render(CLI::App& app);
void register_check(CLI::App& app);
void register_sdf(CLI::App& app);

inline void register_commands(CLI::App& app) {
  register_info(app);
  register_eval(app);
  register_render(app);
  register_check(app);
  register_sdf(app);
}

}  // namespace frep::cli
