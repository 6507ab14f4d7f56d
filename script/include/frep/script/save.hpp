// Saves an expression to a file in the format its extension names.
#pragma once

#include <string>

#include "frep/expr/graph.hpp"
#include "frep/expr/model.hpp"
#include "frep/io/frep_file.hpp"

namespace frep {

// `.vm` (Fidget's text format), `.rhai` (a Fidget script) or `.frep` (frep's binary format);
// written atomically. A device (is_device: /dev/null) gets .frep, written in place. Throws
// InputError for another extension (naming the supported ones) or an unwritable path.
// `oracles` keeps oracles in .frep files (the mesh codec: their triangles); other formats, and
// .frep without a codec, hold the closed form.
void save_expression(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info = {},
                     const FrepOracleCodec* oracles = nullptr);
// The same with what the model knows of its field (Model::info), which the file keeps.
void save_expression(const std::string& path, const Model& m, const FrepOracleCodec* oracles = nullptr);

// Throws the same InputError as save_expression would for an unsupported extension, so that a
// command can fail before long work.
void check_expression_path(const std::string& path);

}  // namespace frep
