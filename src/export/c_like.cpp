// The statement emitter shared by the C and GLSL exporters (see c_like.hpp).
#include "export/c_like.hpp"

#include "export/export_util.hpp"
#include "frep/error.hpp"
#include "frep/expr/opcode.hpp"

namespace frep::export_detail {
namespace {

// Operator precedence of an inline expression, lowest first. Both languages share C's table for
// the few operators we use.
enum Prec : std::uint8_t { kAdditive = 1, kMultiplicative = 2, kUnary = 3, kPrimary = 4 };

// An inline expression longer than this becomes a local: keeps lines readable and bounds the
// nesting depth the target compiler sees (a million-long chain of single-use nodes would
// otherwise be one million-deep expression).
constexpr std::size_t kMaxInline = 100;

struct Ref {
  std::string text;
  Prec prec = kPrimary;
  bool simple = false;  // a plain name (variable or local): cheap to repeat
};

std::string wrap(Ref& r, Prec need) {
  if (r.prec >= need) return std::move(r.text);
  return "(" + std::move(r.text) + ")";
}

}  // namespace

std::uint64_t ops_present(const Graph& g, const std::vector<NodeId>& order) {
  static_assert(kEngineOpCount <= 64, "one bit per opcode");
  std::uint64_t bits = 0;
  for (NodeId id : order) bits |= std::uint64_t{1} << static_cast<unsigned>(g.node(id).op);
  return bits;
}

std::size_t emit_c_like_body(std::ostream& out, const Graph& g, NodeId root, const std::vector<NodeId>& order,
                             const CLikeDialect& d, std::string_view indent) {
  const std::vector<std::uint32_t> uses = use_counts(g, order, root);
  // Inline text of nodes not yet consumed. Each single-use node is consumed exactly once, so its
  // text is moved out and the memory stays proportional to what is pending.
  std::vector<Ref> refs(root + 1);
  std::size_t locals = 0;
  // An operand taken from a node: shared nodes, variables and constants are copied (they are
  // names or literals), single-use inline expressions are moved.
  auto take = [&](NodeId id) -> Ref {
    Ref& r = refs[id];
    if (r.simple || uses[id] > 1 || g.node(id).op == Op::Const) return r;
    return std::move(r);
  };
  for (NodeId id : order) {
    const Node& n = g.node(id);
    Ref r;
    switch (n.op) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ:
        r.text = d.vars[static_cast<int>(n.op) - static_cast<int>(Op::VarX)];
        r.simple = true;
        refs[id] = std::move(r);
        continue;
      case Op::Const:
        r.text = d.literal(n.value);
        r.prec = r.text[0] == '-' ? kUnary : kPrimary;
        refs[id] = std::move(r);
        continue;
      case Op::Oracle:  // a call: a local if used more than once, like any other call
        FREP_ASSERT(d.oracle, "an oracle in an expression the exporter has no code for");
        r.text = d.oracle(oracle_index(n.value));
        break;
      case Op::Add:
      case Op::Sub:
      case Op::Mul:
      case Op::Div: {
        const bool additive = n.op == Op::Add || n.op == Op::Sub;
        const Prec self = additive ? kAdditive : kMultiplicative;
        Ref a = take(n.a), b = take(n.b);
        // Left-associative: the left operand may be at our level; the right one must bind
        // tighter (f32 arithmetic is not associative) and is never a bare unary minus.
        const Prec need_b = b.prec == kUnary ? kPrimary : static_cast<Prec>(self + 1);
        const char* sym = n.op == Op::Add ? " + " : n.op == Op::Sub ? " - " : n.op == Op::Mul ? " * " : " / ";
        r.text = wrap(a, self) + sym + wrap(b, need_b);
        r.prec = self;
        break;
      }
      case Op::Neg: {
        Ref a = take(n.a);
        r.text = "-" + wrap(a, kPrimary);
        r.prec = kUnary;
        break;
      }
      case Op::Recip: {
        Ref a = take(n.a);
        r.text = d.literal(1.0f) + " / " + wrap(a, kPrimary);
        r.prec = kMultiplicative;
        break;
      }
      case Op::Square: {
        Ref a = take(n.a);
        if (a.simple) {
          r.text = a.text + " * " + a.text;
          r.prec = kMultiplicative;
        } else {
          r.text = std::string(d.call[static_cast<int>(Op::Square)]) + "(" + std::move(a.text) + ")";
        }
        break;
      }
      default: {
        const std::string_view fn = d.call[static_cast<int>(n.op)];
        FREP_ASSERT(!fn.empty(), "no spelling for opcode " + std::string(op_name(n.op)));
        Ref a = take(n.a);
        r.text = std::string(fn) + "(" + std::move(a.text);
        if (op_arity(n.op) == 2) {
          Ref b = take(n.b);
          r.text += ", " + std::move(b.text);
        }
        r.text += ")";
        break;
      }
    }
    if (id != root && (uses[id] > 1 || r.text.size() > kMaxInline)) {
      const std::string name = "t" + std::to_string(locals++);
      out << indent << d.local_decl << name << " = " << r.text << ";\n";
      r.text = name;
      r.prec = kPrimary;
      r.simple = true;
    }
    refs[id] = std::move(r);
  }
  out << indent << "return " << refs[root].text << ";\n";
  return locals;
}

}  // namespace frep::export_detail
