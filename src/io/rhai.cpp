// Reading Rhai scripts into a Model: the entry points of include/frep/io/rhai.hpp; the lexer,
// parser, interpreter, builtins and shape library live in the other rhai_*.cpp files.
#include "frep/io/rhai.hpp"

#include "frep/util/atomic_file.hpp"
#include "io/rhai_interp.hpp"
#include "io/field_info.hpp"

namespace frep {

Model parse_rhai(std::string_view text, const std::string& name, const RhaiOptions& options) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark (editors on Windows)
  Model m;
  rhai::Interp interp(text, name, options, *m.graph);
  m.root = interp.run();
  m.info = detail::leading_field_info(text, "//", name);
  return m;
}

Model read_rhai(const std::string& path, const RhaiOptions& options) {
  const std::string text = read_file(path);
  return parse_rhai(text, path, options);
}

}  // namespace frep
