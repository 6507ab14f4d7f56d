// The Rhai interpreter (see rhai_interp.hpp): statements, expressions, variables and calls.
// Operators on values are in rhai_operators.cpp, conversions to trees in rhai_tree.cpp.
#include "rhai_interp.hpp"

#include <filesystem>

#include "frep/util/memory_budget.hpp"

#include <algorithm>
#include <cmath>

#include "frep/error.hpp"
#include "rhai_operators.hpp"

namespace frep::rhai {

namespace {

// Fidget's math constants (fidget-rhai constants.rs), visible as variables unless shadowed.
struct NamedConstant {
  std::string_view name;
  double value;
};
constexpr NamedConstant kConstants[] = {
    {"PI", 3.14159265358979323846},
    {"E", 2.71828182845904523536},
    {"TAU", 6.28318530717958647692},
    {"SQRT_2", 1.41421356237309504880},
    {"LN_2", 0.693147180559945309417},
    {"LN_10", 2.30258509299404568402},
    {"LOG2_E", 1.44269504088896340736},
    {"LOG10_E", 0.434294481903251827651},
    {"FRAC_PI_2", 1.57079632679489661923},
    {"FRAC_PI_3", 1.04719755119659774615},
    {"FRAC_PI_4", 0.785398163397448309616},
    {"FRAC_PI_6", 0.52359877559829887307},
    {"FRAC_PI_8", 0.39269908169872415481},
    {"FRAC_1_PI", 0.318309886183790671538},
    {"FRAC_2_PI", 0.636619772367581343076},
    {"FRAC_2_SQRT_PI", 1.12837916709551257390},
    {"PHI", 1.61803398874989484820},
    {"GOLDEN_RATIO", 1.61803398874989484820},
    {"FRAC_1_SQRT_2", 0.707106781186547524401},
};

std::uint64_t fn_key(std::uint32_t sym, std::size_t arity) { return static_cast<std::uint64_t>(sym) << 32 | arity; }

}  // namespace

Interp::Interp(std::string_view text, const std::string& name, const RhaiOptions& options, Graph& graph)
    : text_(text),
      name_(name),
      g_(graph),
      lexer_(text, symbols_, strings_),
      parser_(lexer_, statements_, functions_),
      ast_(&statements_),
      max_steps_(options.max_steps ? options.max_steps : 100'000'000ull + 16ull * text.size()),
      // Without a limit given, a share of the machine's memory (about 100 bytes per node while a
      // remap copies the graph, and the evaluators need more later): a script that doubles its
      // expression in a loop stops with a message instead of exhausting memory.
      max_nodes_(options.max_nodes ? options.max_nodes : physical_memory_bytes() / 400),
      load_mesh_(options.load_mesh) {
  // Builtin names first, so that their symbol ids index small tables. (The parser has already
  // read the first token, which may have interned one name before these: that is fine, the
  // tables are indexed by whatever ids the names get.)
  auto reg = [&](const Builtin& b) {
    const std::uint32_t s = symbols_.intern(b.name);
    if (builtin_of_.size() <= s) builtin_of_.resize(s + 1, nullptr);
    builtin_of_[s] = &b;
  };
  for (const Builtin& b : core_builtins()) reg(b);
  for (const Builtin& b : shape_builtins()) reg(b);
  for (const Builtin& b : ugf_builtins()) reg(b);
  auto special = [&](std::string_view n, int code) {
    const std::uint32_t s = symbols_.intern(n);
    if (special_of_.size() <= s) special_of_.resize(s + 1, 0);
    special_of_[s] = static_cast<std::int8_t>(code);
  };
  special("x", 1);
  special("y", 2);
  special("z", 3);
  for (std::size_t i = 0; i < std::size(kConstants); ++i) {
    special(kConstants[i].name, static_cast<int>(4 + i));
    constant_values_.push_back(Value::real(kConstants[i].value));
  }
  axes_[0] = g_.var_x();
  axes_[1] = g_.var_y();
  axes_[2] = g_.var_z();
  for (int i = 0; i < 3; ++i) axis_values_[i] = Value::expr(axes_[i]);
}

void Interp::fail(std::uint32_t pos, const std::string& message) const {
  const LineCol lc = line_col(text_, pos);
  throw InputError(name_, lc.line, "column " + std::to_string(lc.column) + ": " + message, pos);
}

void Interp::check_depth(std::uint32_t depth, std::uint32_t pos) const {
  if (depth > kMaxValueDepth)
    fail(pos, "arrays and maps nested more than " + std::to_string(kMaxValueDepth) + " levels deep");
}

void Interp::step(std::uint32_t pos) {
  cur_pos_ = pos;
  charge(1);
}

void Interp::charge(std::uint64_t units) {
  steps_ += units;
  if (steps_ > max_steps_)
    fail(cur_pos_, "the script ran for more than " + std::to_string(max_steps_) +
                       " steps and was stopped (an endless loop?); see docs/rhai.md for the limit");
  check_nodes(0);
}

void Interp::check_nodes(std::uint64_t more) {
  if (max_nodes_ && g_.size() + more > max_nodes_)
    fail(cur_pos_, "the script built more than " + std::to_string(max_nodes_) +
                       " expression nodes and was stopped (its expression keeps growing: a remap in a loop "
                       "doubles it each time); see docs/rhai.md for the limit");
}

std::string Interp::text_of(const Value& v) {
  std::uint64_t budget = max_steps_ - std::min(steps_, max_steps_);
  const std::uint64_t start = budget;
  std::string s = to_text(v, g_, budget);
  charge(start - budget + s.size() / 16);
  if (budget == 0) charge(1);  // ran out: the limit error
  return s;
}

bool Interp::equal(const Value& a, const Value& b) {
  std::uint64_t budget = max_steps_ - std::min(steps_, max_steps_);
  const std::uint64_t start = budget;
  const bool eq = values_equal(a, b, budget);
  charge(start - budget);
  if (budget == 0) charge(1);
  return eq;
}

ArrayObj& Interp::own_array(Value& v) {
  if (!v.unique()) charge(v.as<ArrayObj>().items.size());
  return mutable_array(v);
}

MapObj& Interp::own_map(Value& v) {
  if (!v.unique()) charge(v.as<MapObj>().items.size());
  return mutable_map(v);
}

StrObj& Interp::own_string(Value& v) {
  if (!v.unique()) charge(v.as<StrObj>().text.size() / 16);
  return mutable_string(v);
}

// ---------------------------------------------------------------------------------------------
// Top level

void Interp::ensure_symbols() {
  if (top_.size() < symbols_.size()) top_.resize(symbols_.size(), kNone);
}

void Interp::register_fns() {
  for (FnDef& f : pending_fns_) {
    if (fn_positions_.count(f.pos)) continue;  // already found by a look-ahead
    const std::uint64_t key = fn_key(f.name, f.params.size());
    if (fn_index_.count(key))
      fail(f.pos, "function `" + std::string(symbols_.name(f.name)) + "` with " + std::to_string(f.params.size()) +
                      " parameter(s) is defined twice");
    fn_positions_.insert(f.pos);
    fn_index_.emplace(key, static_cast<std::uint32_t>(fns_.size()));
    fns_.push_back(std::move(f));
  }
  pending_fns_.clear();
}

// Rhai functions may be called before their definition: on the first call to an unknown name,
// parse the rest of the script once for its function definitions, then come back.
void Interp::scan_ahead_for_functions() {
  scanned_all_ = true;
  const Parser::State state = parser_.save();
  const Ast::Mark mark = statements_.mark();
  std::uint32_t node;
  for (;;) {
    const Ast::Mark fmark = functions_.mark();
    const Parser::Item item = parser_.next(&node, pending_fns_);
    if (item == Parser::Item::End) break;
    if (item == Parser::Item::Function && fn_positions_.count(pending_fns_.back().pos)) {
      pending_fns_.pop_back();
      functions_.truncate(fmark);
    }
    register_fns();
    statements_.truncate(mark);
  }
  parser_.restore(state);
}

NodeId Interp::run() {
  if (text_.size() >= 0xFFFFFFF0u) fail(0, "scripts larger than 4 GB are not supported");
  Value last;
  try {
    std::uint32_t n;
    for (;;) {
      const Ast::Mark fmark = functions_.mark();
      const Parser::Item item = parser_.next(&n, pending_fns_);
      if (item == Parser::Item::End) break;
      if (item == Parser::Item::Function) {
        if (fn_positions_.count(pending_fns_.back().pos)) {  // seen by a look-ahead already
          pending_fns_.pop_back();
          functions_.truncate(fmark);
        }
        register_fns();
        continue;
      }
      ensure_symbols();
      ast_ = &statements_;
      last = eval(n);
      if (flow_ == Flow::Return) {
        last = std::move(flow_value_);
        flow_ = Flow::Normal;
        break;
      }
      if (flow_ != Flow::Normal) fail(statements_[n].pos, "`break` or `continue` outside of a loop");
      statements_.truncate({0, 0});
    }
  } catch (const SyntaxError& e) {
    fail(e.pos, e.message);
  }
  if (!drawn_.empty()) return reduce(Op::Min, drawn_);  // their union, with its facts
  if (last.kind() == Kind::Unit)
    fail(static_cast<std::uint32_t>(text_.size()),
         "the script produced no shape: end it with the shape's expression or call draw(shape)");
  return to_expr(last, static_cast<std::uint32_t>(text_.size()), "the script's value");
}

// ---------------------------------------------------------------------------------------------
// Variables

const Value* Interp::lookup(std::uint32_t sym, std::uint32_t pos) {
  std::uint32_t b = sym < top_.size() ? top_[sym] : kNone;
  if (b != kNone && bindings_[b].frame == frame_) return &bindings_[b].v;
  const int special = sym < special_of_.size() ? special_of_[sym] : 0;
  if (frame_ > 0) {
    // Inside a function, x, y and z are always the axes (Fidget's variable resolver); other
    // names fall back to the global variables (a frep extension: Rhai functions see no globals).
    if (special >= 1 && special <= 3) return &axis_values_[special - 1];
    while (b != kNone && bindings_[b].frame != 0) b = bindings_[b].prev;
    if (b != kNone) return &bindings_[b].v;
  }
  if (special >= 1 && special <= 3) return &axis_values_[special - 1];
  if (special >= 4) return &constant_values_[static_cast<std::size_t>(special - 4)];
  const std::string_view nm = symbols_.name(sym);
  if (find_fn(sym, 0) != kNone || builtin(sym))
    fail(pos, "`" + std::string(nm) + "` is a function, not a variable; call it with `" + std::string(nm) + "(...)`");
  fail(pos, "variable `" + std::string(nm) + "` is not defined");
}

void Interp::bind(std::uint32_t sym, Value v, bool is_const) {
  ensure_symbols();
  const std::uint32_t b = top_[sym];
  if (b != kNone && b >= scope_mark_ && bindings_[b].frame == frame_) {
    // Shadowing a variable of the same block: the old one can never be seen again.
    bindings_[b].v = std::move(v);
    bindings_[b].is_const = is_const;
    return;
  }
  bindings_.push_back({std::move(v), b, sym, frame_, is_const});
  top_[sym] = static_cast<std::uint32_t>(bindings_.size() - 1);
}

void Interp::pop_bindings(std::size_t mark) {
  for (std::size_t i = bindings_.size(); i-- > mark;) top_[bindings_[i].sym] = bindings_[i].prev;
  bindings_.resize(mark);
}

// The storage behind an assignment target or a mutating method's receiver: a variable, then
// indices and properties, copying shared arrays and maps on the way (copy on write).
Value* Interp::place(std::uint32_t target, bool for_write) {
  // Walk down to the variable, collecting the links.
  const std::size_t base = spine_.size();
  std::uint32_t cur = target;
  while (node(cur).kind == NK::Index || node(cur).kind == NK::Prop) {
    spine_.push_back(cur);
    cur = node(cur).a;
  }
  if (node(cur).kind != NK::Var) {
    spine_.resize(base);
    return nullptr;  // not a place: the caller works on a temporary
  }
  // Evaluate the indices first (they may run code that changes variables).
  const std::size_t key_base = args_.size();
  for (std::size_t i = spine_.size(); i-- > base;) {
    const AstNode& link = node(spine_[i]);
    if (link.kind == NK::Index) {
      Value k = eval(link.b);
      if (flow_ != Flow::Normal) {
        spine_.resize(base);
        args_.resize(key_base);
        return nullptr;
      }
      args_.push_back(std::move(k));
    }
  }
  const std::uint32_t sym = node(cur).a;
  std::uint32_t b = sym < top_.size() ? top_[sym] : kNone;
  if (b == kNone || bindings_[b].frame != frame_) {
    const std::string nm(symbols_.name(sym));
    spine_.resize(base);
    args_.resize(key_base);
    if (frame_ > 0 && lookup(sym, node(cur).pos))
      fail(node(cur).pos, "cannot change `" + nm + "` inside a function: functions only change their own variables");
    fail(node(cur).pos, "variable `" + nm + "` is not defined" +
                            (for_write ? std::string(" (declare it with `let ") + nm + " = ...;` first)" : ""));
  }
  if (bindings_[b].is_const)
    fail(node(cur).pos, "`" + std::string(symbols_.name(sym)) + "` is a constant and cannot be changed");
  Value* p = &bindings_[b].v;
  path_.clear();
  std::size_t k = key_base;
  for (std::size_t i = spine_.size(); i-- > base;) {
    const AstNode& link = node(spine_[i]);
    if (link.kind == NK::Index) {
      const Value& key = args_[k++];
      if (p->kind() == Kind::Array) {
        path_.push_back(p);
        ArrayObj& arr = own_array(*p);
        if (key.kind() != Kind::Int) fail(link.pos, std::string("array index must be an integer, not ") + type_name(key));
        std::int64_t idx = key.as_int();
        const auto size = static_cast<std::int64_t>(arr.items.size());
        if (idx < 0) idx += size;
        if (idx < 0 || idx >= size)
          fail(link.pos, "array index " + std::to_string(key.as_int()) + " out of bounds (length " + std::to_string(size) + ")");
        p = &arr.items[static_cast<std::size_t>(idx)];
      } else if (p->kind() == Kind::Map) {
        if (key.kind() != Kind::Str) fail(link.pos, std::string("map index must be a string, not ") + type_name(key));
        path_.push_back(p);
        MapObj& m = own_map(*p);
        p = &m.items[key.as<StrObj>().text];
      } else {
        fail(link.pos, std::string("cannot assign into an element of ") + type_name(*p));
      }
    } else {  // Prop
      if (p->kind() != Kind::Map) {
        if (p->kind() == Kind::Vec && i == base) break;  // a vector component: the caller handles it
        fail(link.pos, std::string("cannot set property `") + std::string(symbols_.name(link.b)) + "` of " + type_name(*p));
      }
      path_.push_back(p);
      MapObj& m = own_map(*p);
      const std::string_view key = symbols_.name(link.b);
      auto it = m.items.find(key);
      if (it == m.items.end()) it = m.items.emplace(std::string(key), Value()).first;
      p = &it->second;
    }
  }
  spine_.resize(base);
  args_.resize(key_base);
  return p;
}

// After a write through place(): the arrays and maps on the path may have grown deeper.
void Interp::update_depths(const Value& leaf, std::uint32_t pos) {
  std::uint32_t d = value_depth(leaf);
  for (std::size_t i = path_.size(); i-- > 0;) {
    Value& c = *path_[i];
    std::uint32_t& cd = c.kind() == Kind::Array ? c.as<ArrayObj>().depth : c.as<MapObj>().depth;
    cd = std::max(cd, d + 1);
    d = cd;
  }
  check_depth(d, pos);
  path_.clear();
}

// ---------------------------------------------------------------------------------------------
// Evaluation

bool Interp::condition(const Value& v, std::uint32_t pos) const {
  if (v.kind() == Kind::Bool) return v.as_bool();
  if (v.kind() == Kind::Expr)
    fail(pos, "a condition cannot depend on an expression of x, y, z (its value differs from point to point); "
              "build the choice into the shape with min, max, compare, and, or");
  fail(pos, std::string("a condition must be a boolean, not ") + type_name(v));
}

struct DepthGuard {
  DepthGuard(int& d, const Interp& in, std::uint32_t pos) : depth(d) {
    if (++depth > kMaxEvalDepth)
      in.fail(pos, "the script nests calls and expressions more than " + std::to_string(kMaxEvalDepth) +
                       " levels deep (frep's limit)");
  }
  ~DepthGuard() { --depth; }
  int& depth;
};

Value Interp::eval(std::uint32_t n) {
  const AstNode& nd = node(n);
  step(nd.pos);
  switch (nd.kind) {
    case NK::Unit: return Value();
    case NK::True: return Value::boolean(true);
    case NK::False: return Value::boolean(false);
    case NK::Int: return Value::integer(int_of(nd));
    case NK::Float: return Value::real(float_of(nd));
    case NK::Str: return make_string(strings_[nd.a]);
    case NK::Var: return *lookup(nd.a, nd.pos);
    default: break;
  }
  DepthGuard guard(depth_, *this, nd.pos);
  switch (nd.kind) {
    case NK::Binary:
    case NK::And:
    case NK::Or:
    case NK::Index:
    case NK::Prop:
    case NK::Method: return eval_chain(n);
    case NK::Unary: {
      Value v = eval(nd.a);
      if (flow_ != Flow::Normal) return Value();
      return eval_unary(node(n), std::move(v));
    }
    case NK::Array: return eval_array(n);
    case NK::Map: return eval_map(n);
    case NK::Call: return eval_call(n);
    case NK::Range: return eval_range(n);
    case NK::If: return eval_if(n);
    case NK::Block: return eval_block(n);
    case NK::While:
    case NK::Loop:
    case NK::DoWhile: return eval_loop(n);
    case NK::For: return eval_for(n);
    case NK::Let: return eval_let(n);
    case NK::Assign: return eval_assign(n);
    case NK::Break:
    case NK::Return: {
      Value v;
      if (nd.a != kNone) {
        v = eval(nd.a);
        if (flow_ != Flow::Normal) return Value();
      }
      flow_value_ = std::move(v);
      flow_ = node(n).kind == NK::Break ? Flow::Break : Flow::Return;
      return Value();
    }
    case NK::Continue: flow_ = Flow::Continue; return Value();
    case NK::Throw: {
      Value v;
      if (nd.a != kNone) {
        v = eval(nd.a);
        if (flow_ != Flow::Normal) return Value();
      }
      fail(node(n).pos, "the script threw: " + (v.kind() == Kind::Unit ? std::string("()") : text_of(v)));
    }
    default: break;
  }
  fail(nd.pos, "internal: unexpected syntax node");
}

Value Interp::eval_unary(const AstNode& n, Value v) {
  switch (static_cast<UnOp>(n.op)) {
    case UnOp::Neg: return negate(*this, v, n.pos);
    case UnOp::Plus:
      if (v.is_number() || v.kind() == Kind::Expr || v.kind() == Kind::Vec) return v;
      fail(n.pos, std::string("unary `+` is not defined for ") + type_name(v));
    case UnOp::Not:
      if (v.kind() == Kind::Bool) return Value::boolean(!v.as_bool());
      if (v.kind() == Kind::Expr) fail(n.pos, "`!` is not defined for expressions; use not(e)");
      fail(n.pos, std::string("`!` needs a boolean, not ") + type_name(v));
  }
  return v;
}

bool Interp::is_mutating_method_on_place(const AstNode& n) const {
  if (n.kind != NK::Method) return false;
  const Builtin* b = builtin(n.a);
  if (!b || !b->mutates || find_fn(n.a, n.c) != kNone) return false;
  std::uint32_t cur = list(n.b, 0);
  while (node(cur).kind == NK::Index || node(cur).kind == NK::Prop) cur = node(cur).a;
  return node(cur).kind == NK::Var;
}

bool Interp::is_chain_link(const AstNode& n) const {
  switch (n.kind) {
    case NK::Binary:
    case NK::And:
    case NK::Or:
    case NK::Index:
    case NK::Prop: return true;
    case NK::Method: return !is_mutating_method_on_place(n);
    default: return false;
  }
}

// Left-nested chains (`a + b + c`, `a.f().g()`, `a[0][1]`) are evaluated with a loop over their
// left spine, so a chain of a million links needs no deeper recursion than one link.
Value Interp::eval_chain(std::uint32_t n) {
  const std::size_t base = spine_.size();
  std::uint32_t cur = n;
  while (is_chain_link(node(cur))) {
    spine_.push_back(cur);
    const AstNode& c = node(cur);
    cur = c.kind == NK::Method ? list(c.b, 0) : c.a;
  }
  Value acc;
  if (node(cur).kind == NK::Method) {  // a mutating method on a variable, at the bottom
    acc = eval_method(cur, nullptr);
  } else {
    acc = eval(cur);
  }
  for (std::size_t i = spine_.size(); i-- > base;) {
    if (flow_ != Flow::Normal) break;
    const std::uint32_t link = spine_[i];
    step(node(link).pos);
    acc = apply_link(link, std::move(acc));
  }
  spine_.resize(base);
  if (flow_ != Flow::Normal) return Value();
  return acc;
}

Value Interp::apply_link(std::uint32_t link, Value acc) {
  const AstNode& l = node(link);
  switch (l.kind) {
    case NK::Binary: {
      Value rhs = eval(l.b);
      if (flow_ != Flow::Normal) return Value();
      return binary_op(*this, static_cast<BinOp>(node(link).op), acc, rhs, node(link).pos);
    }
    case NK::And:
    case NK::Or: {
      const bool is_and = l.kind == NK::And;
      const std::uint32_t pos = l.pos, rhs_node = l.b;
      if (acc.kind() != Kind::Bool) condition(acc, pos);
      if (acc.as_bool() != is_and) return acc;  // short circuit
      Value rhs = eval(rhs_node);
      if (flow_ != Flow::Normal) return Value();
      if (rhs.kind() != Kind::Bool) condition(rhs, pos);
      return rhs;
    }
    case NK::Index: {
      Value key = eval(l.b);
      if (flow_ != Flow::Normal) return Value();
      return index_value(*this, acc, key, node(link).pos);
    }
    case NK::Prop: return property_value(*this, acc, l.b, l.pos);
    case NK::Method: return eval_method(link, &acc);
    default: fail(l.pos, "internal: not a chain link");
  }
}

Value Interp::eval_method(std::uint32_t n, Value* receiver) {
  const AstNode& nd = node(n);
  const std::uint32_t sym = nd.a, lst = nd.b, count = nd.c, pos = nd.pos;
  const std::size_t base = args_.size();
  args_.emplace_back();  // the receiver's slot
  for (std::uint32_t i = 1; i < count; ++i) {
    Value v = eval(list(lst, i));
    if (flow_ != Flow::Normal) {
      args_.resize(base);
      return Value();
    }
    args_.push_back(std::move(v));
  }
  if (receiver) {
    args_[base] = std::move(*receiver);
    return call(sym, base, pos, true);
  }
  // A mutating builtin on a variable (or an element of one): move the value in, call, move the
  // result back, so that `a.push(v)` in a loop does not copy the array every time.
  Value* p = place(list(lst, 0), true);
  if (flow_ != Flow::Normal) {
    args_.resize(base);
    return Value();
  }
  args_[base] = std::move(*p);
  const Builtin* b = builtin(sym);
  Value result;
  try {
    result = invoke(*b, std::span<Value>(args_.data() + base, args_.size() - base), pos);
  } catch (...) {
    *p = std::move(args_[base]);
    throw;
  }
  *p = std::move(args_[base]);
  args_.resize(base);
  update_depths(*p, pos);
  return result;
}

Value Interp::eval_array(std::uint32_t n) {
  const std::uint32_t lst = node(n).a, count = node(n).b;
  auto* arr = new ArrayObj();
  Value out = Value::heap(arr);
  arr->items.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    Value v = eval(list(lst, i));
    if (flow_ != Flow::Normal) return Value();
    arr->depth = std::max(arr->depth, value_depth(v) + 1);
    arr->items.push_back(std::move(v));
  }
  check_depth(arr->depth, node(n).pos);
  return out;
}

Value Interp::eval_map(std::uint32_t n) {
  const std::uint32_t lst = node(n).a, pairs = node(n).b;
  auto* m = new MapObj();
  Value out = Value::heap(m);
  for (std::uint32_t i = 0; i < pairs; ++i) {
    Value v = eval(list(lst, 2 * i + 1));
    if (flow_ != Flow::Normal) return Value();
    m->depth = std::max(m->depth, value_depth(v) + 1);
    m->items[strings_[list(lst, 2 * i)]] = std::move(v);
  }
  check_depth(m->depth, node(n).pos);
  return out;
}

Value Interp::eval_range(std::uint32_t n) {
  const std::uint32_t pos = node(n).pos, a = node(n).a, b = node(n).b;
  const bool inclusive = node(n).flags & 1;
  Value lo = eval(a);
  if (flow_ != Flow::Normal) return Value();
  Value hi = eval(b);
  if (flow_ != Flow::Normal) return Value();
  if (lo.kind() != Kind::Int || hi.kind() != Kind::Int)
    fail(pos, std::string("a range needs integers, not ") + type_name(lo) + " and " + type_name(hi));
  std::int64_t end = hi.as_int();
  if (inclusive) {
    if (end == INT64_MAX) fail(pos, "range end out of bounds");
    ++end;
  }
  return Value::heap(new RangeObj(lo.as_int(), end, 1));
}

Value Interp::eval_block(std::uint32_t n) {
  const std::uint32_t lst = node(n).a, count = node(n).b;
  const std::size_t saved = scope_mark_;
  scope_mark_ = bindings_.size();
  Value last;
  for (std::uint32_t i = 0; i < count; ++i) {
    last = eval(list(lst, i));
    if (flow_ != Flow::Normal) break;
  }
  pop_bindings(scope_mark_);
  scope_mark_ = saved;
  return last;
}

Value Interp::eval_if(std::uint32_t n) {
  const std::uint32_t lst = node(n).a, pairs = node(n).b, otherwise = node(n).c;
  for (std::uint32_t i = 0; i < pairs; ++i) {
    const std::uint32_t cond = list(lst, 2 * i);
    Value c = eval(cond);
    if (flow_ != Flow::Normal) return Value();
    if (condition(c, node(cond).pos)) return eval(list(lst, 2 * i + 1));
  }
  if (otherwise != kNone) return eval(otherwise);
  return Value();
}

Value Interp::eval_loop(std::uint32_t n) {
  const NK kind = node(n).kind;
  const std::uint32_t pos = node(n).pos;
  const std::uint32_t body = kind == NK::While ? node(n).b : node(n).a;
  const std::uint32_t cond = kind == NK::While ? node(n).a : (kind == NK::DoWhile ? node(n).b : kNone);
  const bool until = kind == NK::DoWhile && (node(n).flags & 1);
  for (;;) {
    step(pos);
    if (kind == NK::While) {
      Value c = eval(cond);
      if (flow_ != Flow::Normal) return Value();
      if (!condition(c, node(cond).pos)) break;
    }
    eval(body);
    if (flow_ == Flow::Break) {
      flow_ = Flow::Normal;
      return std::move(flow_value_);
    }
    if (flow_ == Flow::Continue) flow_ = Flow::Normal;
    if (flow_ == Flow::Return) return Value();
    if (kind == NK::DoWhile) {
      Value c = eval(cond);
      if (flow_ != Flow::Normal) return Value();
      if (condition(c, node(cond).pos) == until) break;
    }
  }
  return Value();
}

Value Interp::eval_for(std::uint32_t n) {
  const std::uint32_t pos = node(n).pos, body = node(n).b;
  const std::uint32_t var = list(node(n).c, 0), index_var = list(node(n).c, 1);
  Value it = eval(node(n).a);
  if (flow_ != Flow::Normal) return Value();
  // One iteration: a scope with the loop variable(s), then the body. Returns false to stop.
  Value result;
  auto iteration = [&](Value item, std::int64_t index) {
    step(pos);
    const std::size_t saved = scope_mark_;
    scope_mark_ = bindings_.size();
    bind(var, std::move(item), false);
    if (index_var != kNone) bind(index_var, Value::integer(index), false);
    eval(body);
    pop_bindings(scope_mark_);
    scope_mark_ = saved;
    if (flow_ == Flow::Continue) flow_ = Flow::Normal;
    if (flow_ == Flow::Break) {
      flow_ = Flow::Normal;
      result = std::move(flow_value_);
      return false;
    }
    return flow_ == Flow::Normal;
  };
  switch (it.kind()) {
    case Kind::Range: {
      const RangeObj r = it.as<RangeObj>();
      std::int64_t k = 0;
      for (std::int64_t i = r.lo; r.step > 0 ? i < r.hi : i > r.hi; ++k) {
        if (!iteration(Value::integer(i), k)) break;
        if (__builtin_add_overflow(i, r.step, &i)) break;
      }
      break;
    }
    case Kind::Array: {
      const Value keep = it;  // iterate over a snapshot; the body may change the variable
      const auto& items = keep.as<ArrayObj>().items;
      for (std::size_t i = 0; i < items.size(); ++i)
        if (!iteration(items[i], static_cast<std::int64_t>(i))) break;
      break;
    }
    case Kind::Str: {
      const std::string s = it.as<StrObj>().text;
      charge(s.size() / 16);
      std::int64_t k = 0;
      for (std::size_t i = 0; i < s.size(); ++k) {
        std::size_t len = 1;
        while (i + len < s.size() && (static_cast<unsigned char>(s[i + len]) & 0xC0) == 0x80) ++len;
        if (!iteration(make_string(s.substr(i, len)), k)) break;
        i += len;
      }
      break;
    }
    default: fail(node(node(n).a).pos, std::string("cannot iterate over ") + type_name(it) + " (use a range, an array or a string)");
  }
  return result;
}

Value Interp::eval_let(std::uint32_t n) {
  const std::uint32_t sym = node(n).a, init = node(n).b;
  const bool is_const = node(n).flags & 1;
  Value v;
  if (init != kNone) {
    v = eval(init);
    if (flow_ != Flow::Normal) return Value();
  }
  bind(sym, std::move(v), is_const);
  return Value();
}

Value Interp::eval_assign(std::uint32_t n) {
  const AstNode nd = node(n);
  Value v = eval(nd.b);
  if (flow_ != Flow::Normal) return Value();
  Value* p = place(nd.a, true);
  if (flow_ != Flow::Normal) return Value();
  if (!p) fail(nd.pos, "cannot assign to this expression");
  const AstNode& target = node(nd.a);
  if (target.kind == NK::Prop && p->kind() == Kind::Vec) {  // v.x = 1
    const std::string_view prop = symbols_.name(target.b);
    VecObj& o = p->as<VecObj>();
    const int c = prop == "x" ? 0 : prop == "y" ? 1 : prop == "z" ? 2 : prop == "w" ? 3 : 4;
    if (c >= o.n) fail(target.pos, std::string("`") + std::string(prop) + "` is not a component of " + type_name(*p));
    Value cur = Value::real(o.c[c]);
    if (nd.op != 0) v = binary_op(*this, static_cast<BinOp>(nd.op - 1), cur, v, nd.pos);
    if (!v.is_number()) fail(nd.pos, std::string("a vector component must be a number, not ") + type_name(v));
    if (!p->unique()) *p = make_vec(o.n, o.c[0], o.c[1], o.c[2], o.c[3]);
    p->as<VecObj>().c[c] = v.number();
    return Value();
  }
  if (nd.op == 0) {
    *p = std::move(v);
  } else {
    compound_assign(*this, static_cast<BinOp>(nd.op - 1), *p, v, nd.pos);
  }
  update_depths(*p, nd.pos);
  return Value();
}

// ---------------------------------------------------------------------------------------------
// Calls

std::uint32_t Interp::find_fn(std::uint32_t sym, std::size_t arity) const {
  if (fn_index_.empty()) return kNone;
  auto it = fn_index_.find(fn_key(sym, arity));
  return it == fn_index_.end() ? kNone : it->second;
}

Value Interp::eval_call(std::uint32_t n) {
  const std::uint32_t sym = node(n).a, lst = node(n).b, count = node(n).c, pos = node(n).pos;
  const std::size_t base = args_.size();
  for (std::uint32_t i = 0; i < count; ++i) {
    Value v = eval(list(lst, i));
    if (flow_ != Flow::Normal) {
      args_.resize(base);
      return Value();
    }
    args_.push_back(std::move(v));
  }
  return call(sym, base, pos, false);
}

Value Interp::invoke(const Builtin& b, std::span<Value> args, std::uint32_t pos) {
  try {
    return b.fn(*this, args, pos);
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    fail(pos, "`" + std::string(b.name) + "`: " + e.detail());
  }
}

NodeId Interp::mesh(const std::string& path, std::uint32_t pos) {
  if (!load_mesh_) fail(pos, "`mesh` loads mesh files only where scripts are read from files (frep's commands)");
  if (path.empty()) fail(pos, "`mesh`: the file name is empty");
  std::filesystem::path p(path);
  if (p.is_relative() && !name_.empty()) p = std::filesystem::path(name_).parent_path() / p;
  const std::string key = p.lexically_normal().string();
  if (const auto it = meshes_.find(key); it != meshes_.end()) return it->second;
  check_nodes(1);
  const NodeId n = g_.oracle(load_mesh_(key));
  meshes_.emplace(key, n);
  return n;
}

Value Interp::call(std::uint32_t sym, std::size_t base, std::uint32_t pos, bool method) {
  const std::size_t arity = args_.size() - base;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::uint32_t f = find_fn(sym, arity);
    if (f != kNone) return call_script(f, base, pos);
    if (const Builtin* b = builtin(sym)) {
      Value r = invoke(*b, std::span<Value>(args_.data() + base, arity), pos);
      args_.resize(base);
      return r;
    }
    if (scanned_all_) break;
    scan_ahead_for_functions();
  }
  const std::string nm(symbols_.name(sym));
  std::string have;
  for (const FnDef& f : fns_)
    if (f.name == sym) have += (have.empty() ? "" : ", ") + std::to_string(f.params.size());
  if (!have.empty())
    fail(pos, "function `" + nm + "` takes " + have + " argument(s), not " + std::to_string(arity) +
                  (method ? " (counting the value before the `.`)" : ""));
  if (nm == "rand" || nm == "mix")
    fail(pos, "`" + nm + "` (one of Fidget's newest noise opcodes) is unsupported by frep");
  fail(pos, "unknown function `" + nm + "`");
}

Value Interp::call_script(std::uint32_t fi, std::size_t base, std::uint32_t pos) {
  if (++call_depth_ > kMaxCallDepth)
    fail(pos, "script functions call each other more than " + std::to_string(kMaxCallDepth) +
                  " levels deep (endless recursion?)");
  const FnDef& f = fns_[fi];
  const std::uint32_t body = f.body;
  const std::size_t saved_mark = scope_mark_;
  const Ast* saved_ast = ast_;
  ++frame_;
  scope_mark_ = bindings_.size();
  const std::size_t frame_mark = scope_mark_;
  for (std::size_t i = 0; i < f.params.size(); ++i) bind(fns_[fi].params[i], std::move(args_[base + i]), false);
  args_.resize(base);
  ast_ = &functions_;
  Value r = eval(body);
  if (flow_ == Flow::Return) {
    r = std::move(flow_value_);
    flow_ = Flow::Normal;
  } else if (flow_ != Flow::Normal) {
    fail(pos, "`break` or `continue` outside of a loop in function `" + std::string(symbols_.name(fns_[fi].name)) + "`");
  }
  ast_ = saved_ast;
  pop_bindings(frame_mark);
  scope_mark_ = saved_mark;
  --frame_;
  --call_depth_;
  return r;
}

}  // namespace frep::rhai
