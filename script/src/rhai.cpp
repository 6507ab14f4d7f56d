// Reading Rhai scripts into a Model: the entry points of include/frep/script/rhai.hpp; the lexer,
// parser, interpreter, builtins and shape library live in the other rhai_*.cpp files.
#include "frep/script/rhai.hpp"

#include "frep/util/atomic_file.hpp"
#include "rhai_interp.hpp"
#include "frep/io/field_comments.hpp"

namespace frep {

Model parse_rhai(std::string_view text, const std::string& name, const RhaiOptions& options) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark (editors on Windows)
  Model m;
  rhai::Interp interp(text, name, options, *m.graph);
  m.root = interp.run();
  // The script's own `frep:` comments say what its author knows; the modeling library's facts
  // fill in what they leave unknown.
  m.info = detail::leading_field_info(text, "//", name);
  const FieldInfo built = interp.field(m.root).info;
  if (!(m.info.lipschitz > 0)) m.info.lipschitz = built.lipschitz;
  if (m.info.bounds.empty()) {
    m.info.bounds = built.bounds;
    m.info.growth = built.growth;
  }
  return m;
}

Model read_rhai(const std::string& path, const RhaiOptions& options) {
  const std::string text = read_file(path);
  return parse_rhai(text, path, options);
}

}  // namespace frep
