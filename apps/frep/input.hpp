// The input of every command that works on a field: an expression file, or a mesh converted on
// the way in (with a line on stderr saying so, since a big mesh takes a moment).
#pragma once

#include <string>

#include "frep/expr/model.hpp"

namespace frep::cli {

Model load_input(const std::string& path);

// Help text for such an input argument.
inline constexpr const char* kFieldInputHelp =
    "Expression (.vm, .rhai, .frep) or closed mesh (.stl, .obj, .ply, .off; converted first, as by frep convert)";

}  // namespace frep::cli
