// Loads an expression from a file, choosing the reader by extension.
#pragma once

#include <string>

#include "frep/expr/model.hpp"

namespace frep {

// `.vm` (Fidget's text format); other extensions are read as `.vm` too, since it is the only
// expression format so far. Throws InputError naming the file and line.
Model load_expression(const std::string& path);

}  // namespace frep
