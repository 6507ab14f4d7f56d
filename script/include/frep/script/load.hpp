// Loading any file frep reads: expressions in every format (the script language's included) and
// meshes as fields. The one place that knows every input format, above the library and the
// script language.
#pragma once

#include <string>

#include "frep/convert/convert.hpp"
#include "frep/expr/model.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/script/rhai.hpp"

namespace frep {

// `.frep` (frep's binary format, frep/io/frep_file.hpp) by its magic bytes; `.vm` (Fidget's
// text format) and `.rhai` (Fidget's scripts, frep/script/rhai.hpp) by extension; other files are
// read as `.vm` if their first instruction line looks like one (`<id> <opcode>` with a known
// opcode), else as Rhai. Throws InputError naming the file and the line or byte.
// `rhai` applies to scripts; `oracles` reads the oracles a .frep file holds (a file with some
// needs it: load_field passes the mesh codec).
Model load_expression(const std::string& path, const RhaiOptions& rhai = {}, const FrepOracleCodec* oracles = nullptr);

// What every command that takes an expression accepts: an expression file (.vm, .rhai, .frep),
// or a mesh file (.stl, .obj, .ply, .off, told apart by extension), read, checked as
// convert_mesh checks it (refused as it refuses) and loaded as a mesh oracle
// (frep/convert/mesh_oracle.hpp): a one-node expression whose closed form is convert_mesh's with
// `options`. `stats`, when given, receives the mesh's figures (triangles, vertices, box, read
// warnings, seconds to read and index; nodes = 1), untouched for expressions.
Model load_field(const std::string& path, const ConvertOptions& options = {}, ConvertStats* stats = nullptr);

}  // namespace frep
