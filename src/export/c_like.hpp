// Private: the statement emitter shared by the C and GLSL exporters. Turns an expression DAG into
// straight-line code: nodes used more than once (and expressions that grew too long to inline)
// become local variables, everything else is written inline with minimal parentheses.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "frep/expr/graph.hpp"
#include "frep/expr/opcode.hpp"

namespace frep::export_detail {

// How a C-like language spells the parts of an expression.
struct CLikeDialect {
  std::array<std::string_view, 3> vars;  // the x, y, z inputs, e.g. "x" or "p.x"
  std::string_view local_decl;           // prefix of a local definition, e.g. "const float "
  std::string (*literal)(float);         // a float literal (may start with '-')
  // The function called for each call-style opcode (abs, sqrt, min, ...), and for Square when
  // its argument is not a plain name. Add/Sub/Mul/Div/Neg/Recip are written with operators.
  std::array<std::string_view, kOpCount> call;
  // The text of an Op::Oracle node, by its index in the graph's oracles (a call of the code the
  // exporter wrote for it). Unset: the expression must hold no oracles.
  std::function<std::string(std::uint32_t)> oracle;
};

// Bit i set when opcode i occurs in `order` (for emitting only the helpers that are needed);
// 64 bits, since the engine's Op::Oracle is opcode 32.
std::uint64_t ops_present(const Graph& g, const std::vector<NodeId>& order);

// Writes the body of a function returning the value of `root`: one local per shared or long
// subexpression, then `return ...;`. Each line is indented by `indent`. Iterative and linear in
// the number of nodes. Returns the number of locals written.
std::size_t emit_c_like_body(std::ostream& out, const Graph& g, NodeId root, const std::vector<NodeId>& order,
                             const CLikeDialect& d, std::string_view indent);

}  // namespace frep::export_detail
