// The input of every command that works on a field: an expression file, or a mesh converted on
// the way in (with a line on stderr saying so, since a big mesh takes a moment).
#pragma once

#include <string>

#include "frep/convert/convert.hpp"
#include "frep/expr/model.hpp"

namespace frep::cli {

// `stats`, when given, receives the conversion's figures (triangles = 0 for an expression file).
Model load_input(const std::string& path, ConvertStats* stats = nullptr);

// Help text for such an input argument.
inline constexpr const char* kFieldInputHelp =
    "Expression (.vm, .rhai, .frep) or closed mesh (.stl, .obj, .ply, .off; converted first, as by frep convert)";

}  // namespace frep::cli
