// Loads an expression from a file, choosing the reader by content, then by extension.
#pragma once

#include <string>

#include "frep/expr/model.hpp"

namespace frep {

// `.frep` (frep's binary format, recognized by its magic bytes) or `.vm` (Fidget's text format;
// anything else is read as .vm). Throws InputError naming the file and the line or byte.
Model load_expression(const std::string& path);

}  // namespace frep
