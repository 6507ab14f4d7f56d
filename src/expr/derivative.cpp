// Symbolic gradients (derivative.hpp): forward-mode differentiation of the graph into the graph.
// Every rule copies the matching line of GradEvaluator (src/eval/grad_eval.cpp), operation for
// operation, so the two agree bit for bit wherever intermediate values are finite.
#include "frep/expr/derivative.hpp"

#include <algorithm>

#include "frep/error.hpp"
#include "frep/expr/oracle.hpp"

namespace frep {
namespace {

// Ops whose partial derivative can be infinite or NaN at finite arguments.
bool partial_may_blow_up(Op op) {
  switch (op) {
    case Op::Recip:
    case Op::Div:
    case Op::Ln:
    case Op::Asin:
    case Op::Acos:
    case Op::Atan2:
    case Op::Mod:
      return true;
    default:
      return false;
  }
}

// Node builders that drop zero terms. A derivative that is the constant 0 (either sign) stands
// for "no dependence".
class Build {
 public:
  explicit Build(Graph& g) : g_(g), zero_(g.constant(0.0f)) {}

  NodeId zero() const { return zero_; }
  bool is_zero(NodeId id) const {
    const Node& n = g_.node(id);
    return n.op == Op::Const && n.value == 0.0f;
  }
  NodeId c(float v) { return g_.constant(v); }
  NodeId un(Op op, NodeId a) { return g_.unary(op, a); }
  NodeId bin(Op op, NodeId a, NodeId b) { return g_.binary(op, a, b); }

  NodeId add(NodeId a, NodeId b) {
    if (is_zero(a)) return b;
    if (is_zero(b)) return a;
    return bin(Op::Add, a, b);
  }
  NodeId sub(NodeId a, NodeId b) {
    if (is_zero(b)) return a;
    if (is_zero(a)) return neg(b);
    return bin(Op::Sub, a, b);
  }
  NodeId neg(NodeId a) { return is_zero(a) ? zero_ : un(Op::Neg, a); }

  // The chain-rule term p * d, with the evaluator's rule that a zero partial gives 0 even where d
  // is infinite or NaN. That needs a guard, and(p, p * d), only where d may blow up and p may be 0.
  NodeId scale(NodeId p, NodeId d, bool d_wild, bool p_never_zero = false) {
    if (is_zero(p) || is_zero(d)) return zero_;
    const Node& np = g_.node(p);
    const bool p_nonzero = p_never_zero || (np.op == Op::Const && np.value != 0.0f);
    const NodeId prod = bin(Op::Mul, p, d);
    return (d_wild && !p_nonzero) ? bin(Op::And, p, prod) : prod;
  }

  // k != 0 ? x : y, where nk is zero exactly where k is not (the evaluator's choice rules), as
  // and(k, x) + and(nk, y): the unchosen side is exactly 0 (and returns its zero first argument),
  // so the value is the chosen side's, and so is the gradient, also where that side is exactly 0
  // (or(and(k, x), and(nk, y)) would fall through to a constant there: second derivatives of 0).
  NodeId select(NodeId k, NodeId nk, NodeId x, NodeId y) {
    if (x == y) return x;
    if (is_zero(x) && is_zero(y)) return zero_;
    if (is_zero(x)) return bin(Op::And, nk, y);  // nk == 0 returns nk, a zero
    if (is_zero(y)) return bin(Op::And, k, x);
    return bin(Op::Add, bin(Op::And, k, x), bin(Op::And, nk, y));
  }

  // -1 where a < 0, else +1 (so abs'(0) = +1): or(compare(a, 0), 1).
  NodeId sign_plus(NodeId a) { return bin(Op::Or, bin(Op::Compare, a, zero_), c(1.0f)); }

 private:
  Graph& g_;
  NodeId zero_;
};

}  // namespace

Gradient Differentiator::grad(Expr e) {
  FREP_ASSERT(&e.graph() == g_, "expression from a different graph");
  Graph& g = *g_;
  const NodeId root = e.id();
  if (memo_.size() < g.size()) memo_.resize(g.size());
  if (memo_[root].d[0] == kNoNode) {
    // Collect the nodes below root that have no derivatives yet (depth-first, explicit stack),
    // then differentiate them in increasing id order, which is topological.
    std::vector<NodeId> todo, stack{root};
    std::vector<std::uint8_t> seen(root + 1, 0);
    seen[root] = 1;
    while (!stack.empty()) {
      const NodeId id = stack.back();
      stack.pop_back();
      todo.push_back(id);
      const Node& n = g.node(id);
      for (NodeId arg : {n.a, n.b}) {
        if (arg == kNoNode || seen[arg] || memo_[arg].d[0] != kNoNode) continue;
        seen[arg] = 1;
        stack.push_back(arg);
      }
    }
    std::sort(todo.begin(), todo.end());
    for (NodeId id : todo) compute(id);
  }
  const Entry& r = memo_[root];
  return {Expr(g, r.d[0]), Expr(g, r.d[1]), Expr(g, r.d[2])};
}

void Differentiator::compute(NodeId id) {
  Graph& g = *g_;
  Build b(g);
  const Node n = g.node(id);  // a copy: building nodes may reallocate the arena
  Entry out;
  for (NodeId& d : out.d) d = b.zero();

  switch (n.op) {
    case Op::VarX:
    case Op::VarY:
    case Op::VarZ:
      out.d[static_cast<int>(n.op) - static_cast<int>(Op::VarX)] = b.c(1.0f);
      memo_[id] = out;
      return;
    case Op::Const:
      memo_[id] = out;
      return;
    case Op::Oracle: {
      // Its partial derivatives are oracles too (GradientOracle).
      const std::shared_ptr<const Oracle> o = g.oracles()[oracle_index(n.value)];  // a copy: the table grows
      for (int a = 0; a < 3; ++a) out.d[a] = g.oracle(std::make_shared<const GradientOracle>(o, a));
      memo_[id] = out;
      return;
    }
    default:
      break;
  }

  const bool binary = op_arity(n.op) == 2;
  const Entry ea = memo_[n.a];
  Entry eb;
  for (NodeId& d : eb.d) d = b.zero();
  if (binary) eb = memo_[n.b];
  auto all_zero = [&](const Entry& e) { return b.is_zero(e.d[0]) && b.is_zero(e.d[1]) && b.is_zero(e.d[2]); };
  const bool za = all_zero(ea), zb = all_zero(eb);
  if (za && zb) {
    memo_[id] = out;
    return;
  }
  const NodeId a = n.a, bb = n.b;
  const NodeId v = id;  // the node's own value
  out.wild = ea.wild || eb.wild || partial_may_blow_up(n.op);

  // d = pa * da + pb * db, each partial built only if its side has a derivative.
  auto chain = [&](auto make_pa, auto make_pb, bool pa_never_zero = false) {
    const NodeId pa = za ? b.zero() : make_pa();
    const NodeId pb = zb ? b.zero() : make_pb();
    for (int k = 0; k < 3; ++k)
      out.d[k] = b.add(b.scale(pa, ea.d[k], ea.wild, pa_never_zero), b.scale(pb, eb.d[k], eb.wild));
  };
  auto none = [&] { return b.zero(); };
  // A choice: the derivative of the side returned, selected where k != 0 (nk == 0 there).
  auto choose = [&](auto make_k) {
    bool same = true;
    for (int k = 0; k < 3; ++k) same = same && ea.d[k] == eb.d[k];
    if (same) {
      out = ea;
      return;
    }
    const auto [k, nk] = make_k();
    for (int i = 0; i < 3; ++i) out.d[i] = b.select(k, nk, ea.d[i], eb.d[i]);
    out.wild = ea.wild || eb.wild;
  };

  switch (n.op) {
    case Op::Neg:
      for (int k = 0; k < 3; ++k) out.d[k] = b.neg(ea.d[k]);
      break;
    case Op::Abs:  // a < 0 ? -da : da, as a multiplication by exactly -1 or +1
      chain([&] { return b.sign_plus(a); }, none, true);
      break;
    case Op::Recip:  // -1 / (a * a)
      chain([&] { return b.bin(Op::Div, b.c(-1.0f), b.un(Op::Square, a)); }, none);
      break;
    case Op::Sqrt:  // v == 0 ? 0 : 0.5 / v, which is and(v, 0.5 / v)
      chain([&] { return b.bin(Op::And, v, b.bin(Op::Div, b.c(0.5f), v)); }, none);
      break;
    case Op::Square:
      chain([&] { return b.bin(Op::Mul, b.c(2.0f), a); }, none);
      break;
    case Op::Sin:
      chain([&] { return b.un(Op::Cos, a); }, none);
      break;
    case Op::Cos:
      chain([&] { return b.un(Op::Neg, b.un(Op::Sin, a)); }, none);
      break;
    case Op::Tan:  // 1 + v * v
      chain([&] { return b.bin(Op::Add, b.c(1.0f), b.un(Op::Square, v)); }, none);
      break;
    case Op::Asin:  // 1 / sqrt(1 - a * a)
      chain([&] { return b.bin(Op::Div, b.c(1.0f), b.un(Op::Sqrt, b.bin(Op::Sub, b.c(1.0f), b.un(Op::Square, a)))); },
            none);
      break;
    case Op::Acos:  // -1 / sqrt(1 - a * a)
      chain([&] { return b.bin(Op::Div, b.c(-1.0f), b.un(Op::Sqrt, b.bin(Op::Sub, b.c(1.0f), b.un(Op::Square, a)))); },
            none);
      break;
    case Op::Atan:  // 1 / (1 + a * a)
      chain([&] { return b.bin(Op::Div, b.c(1.0f), b.bin(Op::Add, b.c(1.0f), b.un(Op::Square, a))); }, none);
      break;
    case Op::Exp:
      chain([&] { return v; }, none);
      break;
    case Op::Ln:
      chain([&] { return b.bin(Op::Div, b.c(1.0f), a); }, none);
      break;
    case Op::Add:
      for (int k = 0; k < 3; ++k) out.d[k] = b.add(ea.d[k], eb.d[k]);
      break;
    case Op::Sub:
      for (int k = 0; k < 3; ++k) out.d[k] = b.sub(ea.d[k], eb.d[k]);
      break;
    case Op::Mul:
      chain([&] { return bb; }, [&] { return a; });
      break;
    case Op::Div:  // 1 / b and -(a / (b * b))
      chain([&] { return b.bin(Op::Div, b.c(1.0f), bb); },
            [&] { return b.un(Op::Neg, b.bin(Op::Div, a, b.un(Op::Square, bb))); });
      break;
    case Op::Atan2: {  // atan2(y = a, x = b): b / (a*a + b*b) and -a / (a*a + b*b)
      auto den = [&] { return b.bin(Op::Add, b.un(Op::Square, a), b.un(Op::Square, bb)); };
      chain([&] { return b.bin(Op::Div, bb, den()); }, [&] { return b.bin(Op::Div, b.un(Op::Neg, a), den()); });
      break;
    }
    case Op::Mod:  // 1 and -floor(a / |b|) * (b < 0 ? -1 : 1)
      chain([&] { return b.c(1.0f); },
            [&] {
              const NodeId q = b.un(Op::Floor, b.bin(Op::Div, a, b.un(Op::Abs, bb)));
              return b.bin(Op::Mul, b.un(Op::Neg, q), b.sign_plus(bb));
            });
      break;
    case Op::Min:  // a < b: k = min(compare(a, b), 0) is -1 there and 0 elsewhere
      choose([&] {
        const NodeId k = b.bin(Op::Min, b.bin(Op::Compare, a, bb), b.zero());
        return std::pair{k, b.un(Op::Not, k)};
      });
      break;
    case Op::Max:  // a > b: k = max(compare(a, b), 0)
      choose([&] {
        const NodeId k = b.bin(Op::Max, b.bin(Op::Compare, a, bb), b.zero());
        return std::pair{k, b.un(Op::Not, k)};
      });
      break;
    case Op::And:  // a == 0 ? da : db
      choose([&] { return std::pair{b.un(Op::Not, a), a}; });
      break;
    case Op::Or:  // a != 0 ? da : db
      choose([&] { return std::pair{a, b.un(Op::Not, a)}; });
      break;
    default:  // floor, ceil, round, compare, not: piecewise constant
      out = Entry{};
      for (NodeId& d : out.d) d = b.zero();
      break;
  }
  memo_[id] = out;
}

Gradient grad(Expr e) {
  Differentiator d(e.graph());
  return d.grad(e);
}

Expr dot(const Gradient& a, const Gradient& b) {
  Graph& g = a.x.graph();
  Build bd(g);
  NodeId sum = bd.zero();
  const Expr* pa[3] = {&a.x, &a.y, &a.z};
  const Expr* pb[3] = {&b.x, &b.y, &b.z};
  for (int k = 0; k < 3; ++k) {
    FREP_ASSERT(&pa[k]->graph() == &g && &pb[k]->graph() == &g, "gradients from different graphs");
    if (bd.is_zero(pa[k]->id()) || bd.is_zero(pb[k]->id())) continue;
    sum = bd.add(sum, bd.bin(Op::Mul, pa[k]->id(), pb[k]->id()));
  }
  return Expr(g, sum);
}

Expr length(const Gradient& g) { return sqrt(dot(g, g)); }

Expr grad_dot(Expr a, Expr b) {
  Differentiator d(a.graph());
  const Gradient ga = d.grad(a);
  const Gradient gb = d.grad(b);
  return dot(ga, gb);
}

}  // namespace frep
