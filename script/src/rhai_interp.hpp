// The Rhai interpreter: walks the syntax tree one top-level statement at a time, keeps variables
// in one binding stack (a per-symbol chain gives O(1) lookups even with millions of globals),
// and builds the expression graph as scripts do arithmetic on x, y and z. Builtins (rhai_
// builtins.cpp) and Fidget's shape library (rhai_shapes.cpp) are plain functions over values.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "frep/math/affine.hpp"
#include "frep/expr/graph.hpp"
#include "frep/script/rhai.hpp"
#include "frep/model/field.hpp"
#include "rhai_ast.hpp"
#include "rhai_lexer.hpp"
#include "rhai_parser.hpp"
#include "rhai_value.hpp"

namespace frep::rhai {

// Script functions may call each other this deep (Rhai's default, kept by Fidget, is 64).
inline constexpr int kMaxCallDepth = 200;
// Evaluation may recurse this deep in all (nested calls times the nesting inside them); beyond
// it the script stops with an error instead of exhausting the native stack. At the limit the
// reader uses less than 1 MB of stack in a release build (under 4 MB with AddressSanitizer).
inline constexpr int kMaxEvalDepth = 3000;

class Interp;

// A builtin receives its evaluated arguments (it may modify them: a mutating method changes
// args[0], which the interpreter writes back to the receiver) and the call's position.
using BuiltinFn = Value (*)(Interp& in, std::span<Value> args, std::uint32_t pos);
struct Builtin {
  std::string_view name;
  BuiltinFn fn;
  bool mutates = false;
};
std::span<const Builtin> core_builtins();   // rhai_builtins.cpp
std::span<const Builtin> shape_builtins();  // rhai_shapes.cpp
std::span<const Builtin> ugf_builtins();    // rhai_ugf.cpp: the unit gradient field library

class Interp {
 public:
  Interp(std::string_view text, const std::string& name, const RhaiOptions& options, Graph& graph);
  Interp(const Interp&) = delete;
  Interp& operator=(const Interp&) = delete;

  // Runs the script; returns the shape (what `draw` received, or the script's last value).
  NodeId run();

  // ---- for builtins -----------------------------------------------------------------------
  Graph& graph() { return g_; }
  [[noreturn]] void fail(std::uint32_t pos, const std::string& message) const;
  std::string_view symbol_name(std::uint32_t sym) const { return symbols_.name(sym); }
  // Work accounting: bulk operations (copies, concatenations, traversals, remaps) cost one step
  // per element, so the step limit bounds time and memory for every script.
  void charge(std::uint64_t units);
  std::string text_of(const Value& v);
  bool equal(const Value& a, const Value& b);
  // Copy on write, charged.
  ArrayObj& own_array(Value& v);
  MapObj& own_map(Value& v);
  StrObj& own_string(Value& v);

  // Fidget's conversion of a value to a tree: expressions, numbers (constants), arrays (their
  // union) and planes. `what` names the argument in the error message.
  NodeId to_expr(const Value& v, std::uint32_t pos, const std::string& what);
  NodeId constant(double v) { return g_.constant(static_cast<float>(v)); }
  NodeId unary(Op op, NodeId a) { return g_.unary(op, a); }
  NodeId binary(Op op, NodeId a, NodeId b) { return g_.binary(op, a, b); }
  // Fidget's union / intersection: balanced trees of min / max; +inf / -inf when empty.
  NodeId reduce(Op op, std::span<const NodeId> items);
  // The expression with x, y, z replaced (Fidget's `remap`; frep::remap, charged).
  NodeId remap(NodeId e, NodeId x, NodeId y, NodeId z);
  // Fails when the graph plus `more` nodes would pass the node limit.
  void check_nodes(std::uint64_t more);
  // The field a node is, with the facts the modeling library recorded for it (keep); plain
  // arithmetic records none. Builtins call the library on these and keep what it returns.
  Field field(NodeId id) const;
  NodeId keep(const Field& f);
  // Charges a remap of `copied` one step per node it may copy, and fails before a copy that the
  // node limit would refuse.
  void charge_remap(NodeId copied);
  // The same for an affine transform of `f` (which remaps f's affine source, if it has one).
  void charge_transform(const Field& f) { charge_remap(f.affine_source != kNoNode ? f.affine_source : f.id()); }
  NodeId var(int axis) const { return axes_[axis]; }
  // Records a shape for `draw`.
  void draw(NodeId shape) { drawn_.push_back(shape); }
  // The oracle of the mesh file `path` names (relative to the script's folder), through
  // RhaiOptions::load_mesh; the same file once per script.
  NodeId mesh(const std::string& path, std::uint32_t pos);
  // Errors if an array or map would nest deeper than kMaxValueDepth.
  void check_depth(std::uint32_t depth, std::uint32_t pos) const;

 private:
  // Control flow out of a block: break, continue, return.
  enum class Flow : std::uint8_t { Normal, Break, Continue, Return };

  const AstNode& node(std::uint32_t n) const { return (*ast_)[n]; }
  std::uint32_t list(std::uint32_t start, std::uint32_t i) const { return ast_->lists[start + i]; }

  Value eval(std::uint32_t n);
  Value eval_chain(std::uint32_t n);
  Value apply_link(std::uint32_t link, Value acc);
  Value eval_block(std::uint32_t n);
  Value eval_if(std::uint32_t n);
  Value eval_loop(std::uint32_t n);
  Value eval_for(std::uint32_t n);
  Value eval_array(std::uint32_t n);
  Value eval_map(std::uint32_t n);
  Value eval_let(std::uint32_t n);
  Value eval_assign(std::uint32_t n);
  Value eval_call(std::uint32_t n);
  Value eval_method(std::uint32_t n, Value* receiver);
  Value eval_range(std::uint32_t n);
  Value eval_unary(const AstNode& n, Value v);
  bool is_chain_link(const AstNode& n) const;
  bool is_mutating_method_on_place(const AstNode& n) const;

  // Runs a builtin; an InputError it throws without a file (a library check) becomes a script
  // error at `pos`.
  Value invoke(const Builtin& b, std::span<Value> args, std::uint32_t pos);
  // Calls a function by name with arguments on args_ from `base`; pops them.
  Value call(std::uint32_t sym, std::size_t base, std::uint32_t pos, bool method);
  Value call_script(std::uint32_t fn, std::size_t base, std::uint32_t pos);
  const Builtin* builtin(std::uint32_t sym) const {
    return sym < builtin_of_.size() ? builtin_of_[sym] : nullptr;
  }
  std::uint32_t find_fn(std::uint32_t sym, std::size_t arity) const;
  void register_fns();
  void scan_ahead_for_functions();

  // Variables.
  const Value* lookup(std::uint32_t sym, std::uint32_t pos);
  Value* place(std::uint32_t target, bool for_write);
  void update_depths(const Value& leaf, std::uint32_t pos);
  void bind(std::uint32_t sym, Value v, bool is_const);
  void pop_bindings(std::size_t mark);
  void ensure_symbols();

  // Truthiness of a condition (Rhai: booleans only).
  bool condition(const Value& v, std::uint32_t pos) const;
  void step(std::uint32_t pos);

  std::string_view text_;
  std::string name_;
  Graph& g_;
  Symbols symbols_;
  std::vector<std::string> strings_;
  Lexer lexer_;
  Ast statements_, functions_;
  Parser parser_;
  const Ast* ast_;

  std::vector<FnDef> fns_, pending_fns_;
  std::unordered_map<std::uint64_t, std::uint32_t> fn_index_;  // (symbol, arity) -> fns_ index
  std::unordered_set<std::uint32_t> fn_positions_;
  bool scanned_all_ = false;
  std::vector<const Builtin*> builtin_of_;  // by symbol id
  std::vector<std::int8_t> special_of_;     // by symbol id: 1..3 = x, y, z; 4.. = a math constant

  struct Binding {
    Value v;
    std::uint32_t prev;   // the binding this one shadows (same symbol), or kNone
    std::uint32_t sym;
    std::uint32_t frame;  // 0 = global; one more per nested script call
    bool is_const;
  };
  std::vector<Binding> bindings_;
  std::vector<std::uint32_t> top_;  // newest binding per symbol
  std::size_t scope_mark_ = 0;      // first binding of the innermost block
  std::uint32_t frame_ = 0;

  std::vector<Value> args_;          // argument stack
  std::vector<std::uint32_t> spine_;  // left spines of chains being evaluated
  std::vector<Value*> path_;          // containers on the way to the last place()

  Flow flow_ = Flow::Normal;
  Value flow_value_;
  std::uint64_t steps_ = 0, max_steps_;
  std::uint32_t cur_pos_ = 0;  // position of the latest step, for errors found inside helpers
  std::uint64_t max_nodes_;
  int depth_ = 0, call_depth_ = 0;

  NodeId axes_[3];
  Value axis_values_[3];
  std::vector<Value> constant_values_;  // Fidget's math constants, by their index
  std::vector<NodeId> drawn_;
  // What the modeling library knows of the nodes it built (FieldInfo, the affine source).
  struct Facts {
    FieldInfo info;
    NodeId affine_source = kNoNode;
    Affine3 affine;
  };
  std::unordered_map<NodeId, Facts> facts_;
  std::function<std::shared_ptr<const Oracle>(const std::string&)> load_mesh_;
  std::unordered_map<std::string, NodeId> meshes_;  // resolved path -> its oracle node
};

}  // namespace frep::rhai
