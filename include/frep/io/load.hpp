// Loads an expression from a file, choosing the reader by extension, else by content.
#pragma once

#include <string>

#include "frep/expr/model.hpp"

namespace frep {

// `.vm` (Fidget's text format) and `.rhai` (Fidget's scripts, frep/io/rhai.hpp) by extension;
// other files are read as `.vm` if their first instruction line looks like one (`<id> <opcode>`
// with a known opcode), else as Rhai. Throws InputError naming the file and line.
Model load_expression(const std::string& path);

}  // namespace frep
