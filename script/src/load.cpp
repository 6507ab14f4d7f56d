// Loading an expression file: .frep by its magic bytes, `.vm` and `.rhai` by extension, anything
// else by content.
#include "frep/script/load.hpp"

#include <string_view>

#include "frep/error.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/script/rhai.hpp"
#include "frep/io/vm.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && std::string_view(s).substr(s.size() - suffix.size()) == suffix;
}

// A `.vm` file's first instruction line is `<id> <opcode> [args]`: a known opcode and as many
// arguments as it takes (`#` starts a comment). A Rhai script's first line never is: its
// comments start with `//`, and a statement such as `let square = ...` has `=` or parentheses.
bool looks_like_vm(std::string_view text) {
  auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
  std::size_t pos = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // UTF-8 byte order mark
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::string_view tok[5];
    int n = 0;
    for (std::size_t i = 0; i < line.size() && n < 5;) {
      while (i < line.size() && is_space(line[i])) ++i;
      std::size_t j = i;
      while (j < line.size() && !is_space(line[j])) ++j;
      if (j > i) tok[n++] = line.substr(i, j - i);
      i = j;
    }
    if (n == 0) continue;  // blank or comment: look at the next line
    if (n < 2 || line.find_first_of("=(){};[]\"") != std::string_view::npos) return false;
    const auto op = op_from_name(tok[1]);
    if (!op) return false;
    return n - 2 == (*op == Op::Const ? 1 : op_arity(*op));
  }
  return false;
}

}  // namespace

Model load_expression(const std::string& path, const RhaiOptions& rhai, const FrepOracleCodec* oracles) {
  const std::string text = read_file(path);
  if (is_frep_file(text) || ends_with(path, ".frep")) return parse_frep(text, path, oracles);  // a bad one says what is wrong
  if (ends_with(path, ".vm")) return parse_vm(text, path);
  if (ends_with(path, ".rhai")) return parse_rhai(text, path, rhai);
  if (looks_like_vm(text)) return parse_vm(text, path);
  // Binary content with another extension (an image, an archive): say so rather than report a
  // Rhai syntax error at its first byte.
  if (std::string_view(text).substr(0, 4096).find('\0') != std::string_view::npos || text.rfind("\x89PNG", 0) == 0)
    throw InputError(path, 0, "not an expression file (binary content): expected a .vm, .rhai or .frep expression, "
                              "or a mesh (.stl, .obj, .ply, .off)");
  return parse_rhai(text, path, rhai);
}

}  // namespace frep
