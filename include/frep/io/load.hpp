// Loads an expression from a file, choosing the reader by content and extension.
#pragma once

#include <string>

#include "frep/expr/model.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/rhai.hpp"

namespace frep {

// `.frep` (frep's binary format, frep/io/frep_file.hpp) by its magic bytes; `.vm` (Fidget's
// text format) and `.rhai` (Fidget's scripts, frep/io/rhai.hpp) by extension; other files are
// read as `.vm` if their first instruction line looks like one (`<id> <opcode>` with a known
// opcode), else as Rhai. Throws InputError naming the file and the line or byte.
// `rhai` applies to scripts; `oracles` reads the oracles a .frep file holds (a file with some
// needs it: load_field passes the mesh codec).
Model load_expression(const std::string& path, const RhaiOptions& rhai = {}, const FrepOracleCodec* oracles = nullptr);

}  // namespace frep
