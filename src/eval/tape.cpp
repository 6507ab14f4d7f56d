#include "frep/eval/tape.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "frep/error.hpp"
#include "frep/expr/oracle.hpp"
#include "eval/caps.hpp"
#include "eval/tape_builder.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {
namespace {

bool foldable(Op op, float lo, float hi) {
  if (!(lo == hi)) return false;  // also false for unknown
  if (lo != 0.0f) return true;
  // A zero interval may hide -0 versus +0; only these ops produce an exact +0.
  return op == Op::Compare || op == Op::Not;
}

// Instruction states during single-box simplification. kLive is a bit no later state clears.
// kAbove: a constant whose value is in the instruction's cap slot (caps::MinCaps::above).
enum : std::uint8_t { kDead = 0, kLive = 1, kKeep = 3, kConst = 5, kLeft = 7, kRight = 9, kAbove = 11 };

}  // namespace

std::uint64_t next_tape_stamp() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

Tape Tape::compile(const Graph& g, NodeId root) {
  const std::vector<NodeId> order = reachable_nodes(g, root);
  std::vector<std::uint32_t> index(root + 1, 0);
  std::vector<SsaInstr> ssa;
  ssa.reserve(order.size());
  for (NodeId id : order) {
    const Node& n = g.node(id);
    SsaInstr ins{n.op, 0, 0, n.value};
    if (n.a != kNoNode) ins.a = index[n.a];
    if (n.b != kNoNode) ins.b = index[n.b];
    index[id] = static_cast<std::uint32_t>(ssa.size());
    ssa.push_back(ins);
  }
  Tape t;
  rebuild(ssa, nullptr, nullptr, t, true);
  if (!g.oracles().empty()) t.oracles_ = std::make_shared<const OracleTable>(g.oracles());
  return t;
}

Tape Tape::from_ssa(const std::vector<SsaInstr>& ssa, std::shared_ptr<const OracleTable> oracles) {
  FREP_ASSERT(!ssa.empty(), "empty tape");
  for (std::size_t i = 0; i < ssa.size(); ++i) {
    const int ar = op_arity(ssa[i].op);
    FREP_ASSERT(ar < 1 || ssa[i].a < i, "argument after its use");
    FREP_ASSERT(ar < 2 || ssa[i].b < i, "argument after its use");
    FREP_ASSERT(ssa[i].op != Op::Oracle || (oracles && oracle_index(ssa[i].value) < oracles->size()),
                "oracle index out of range");
  }
  Tape t;
  rebuild(ssa, nullptr, nullptr, t, true);
  t.oracles_ = std::move(oracles);
  return t;
}

void Tape::simplify(const std::vector<Interval>& values, const std::vector<Choice>& choices, Tape& out,
                    bool registers, float root_cap) const {
  FREP_ASSERT(&out != this, "simplify into itself");
  FREP_ASSERT(values.size() >= ssa_size_ && choices.size() >= ssa_size_, "interval results do not match the tape");
  FREP_ASSERT(!std::isnan(root_cap), "a root cap is a number");
  rebuild(ssa(), values.data(), choices.data(), out, registers, root_cap);
  out.oracles_ = oracles_;
}

Tape Tape::simplified(const std::vector<Interval>& values, const std::vector<Choice>& choices) const {
  Tape out;
  simplify(values, choices, out);
  return out;
}

void Tape::rebuild(std::span<const SsaInstr> src, const Interval* values, const Choice* choices, Tape& out,
                   bool registers, float root_cap) {
  const std::size_t n = src.size();
  FREP_ASSERT(n > 0, "empty tape");
  const SsaInstr* in = src.data();
  // Backward pass: what each instruction the root needs becomes, and its cap (eval/caps.hpp).
  out.state_.assign(n, kDead);
  std::uint8_t* st = out.state_.data();
  if (values && out.caps_.size() < n) out.caps_.resize(n);
  float* cap = out.caps_.data();
  st[n - 1] = kLive;
  if (values) cap[n - 1] = root_cap;
  // Marks j live with cap c (the largest of its caps so far). Below i, only kDead or kLive are set yet.
  const auto use = [&](std::uint32_t j, float c) {
    if (values) cap[j] = st[j] == kDead ? c : std::max(cap[j], c);
    st[j] |= kLive;
  };
  for (std::size_t i = n; i-- > 0;) {
    if (st[i] == kDead) continue;
    const SsaInstr& ins = in[i];
    const int ar = op_arity(ins.op);
    if (values && ar > 0) {
      if (foldable(ins.op, values[i].lo, values[i].hi)) {
        st[i] = kConst;
        continue;
      }
      if (op_is_choice(ins.op)) {
        Choice c = choices[i];
        const float ci = cap[i];
        if (ins.op == Op::Min && c == Choice::Both) {
          const caps::MinCaps mc = caps::min_caps(ci, values[ins.a].lo, values[ins.a].hi, values[ins.b].lo,
                                                  values[ins.b].hi);
          if (mc.above) {
            st[i] = kAbove;
            cap[i] = mc.value;  // its cap is read no more
            continue;
          }
          c = mc.choice;
          if (c == Choice::Both) {
            st[i] = kKeep;
            use(ins.a, mc.cap_a);
            use(ins.b, mc.cap_b);
            continue;
          }
        }
        const bool passes = ins.op == Op::Min || ins.op == Op::Max;
        if (c != Choice::Both) {
          const bool left = c == Choice::Left;
          st[i] = left ? kLeft : kRight;
          use(left ? ins.a : ins.b, passes ? ci : caps::kNone);
          continue;
        }
        st[i] = kKeep;
        use(ins.a, passes ? ci : caps::kNone);
        use(ins.b, passes ? ci : caps::kNone);
        continue;
      }
    }
    st[i] = kKeep;
    if (ar >= 1) use(ins.a, caps::kNone);
    if (ar >= 2) use(ins.b, caps::kNone);
  }
  // Forward pass.
  Builder b(out, n, registers);
  for (std::size_t i = 0; i < n; ++i) {
    switch (st[i]) {
      case kDead: break;
      case kLeft: b.alias(i, in[i].a); break;
      case kRight: b.alias(i, in[i].b); break;
      case kConst: b.constant(i, values[i].lo); break;
      case kAbove: b.constant(i, cap[i]); break;
      default: b.keep(i, in[i]);
    }
  }
  b.finish(n - 1);
}

void Tape::allocate_registers() {
  const std::size_t m = ssa_size_;
  grow_scratch(code_, m);
  if (ssa_[m - 1].op == Op::Const) {
    // A constant root: every other instruction is dead.
    RegInstr r;
    r.op = Op::Const;
    r.imm = ssa_[m - 1].value;
    code_[0] = r;
    code_size_ = 1;
    num_regs_ = 1;
    root_reg_ = 0;
    return;
  }
  // The builder wrote one register per SSA value (out, a and b are SSA indices); this renames
  // them in place in one backward pass: a value takes a register where it is last used (the
  // first use met going backward) and gives it back where it is defined. An instruction's
  // result may share a register with an argument (evaluators read arguments before writing,
  // lane by lane). The scratch is the thread's, not the tape's: many tapes are allocated, few
  // at a time, and tapes only keep what they run.
  constexpr std::uint32_t kUnassigned = UINT32_MAX;
  thread_local std::vector<std::uint32_t> reg_scratch, free_regs;
  grow_scratch(reg_scratch, m);
  std::uint32_t* reg = reg_scratch.data();
  std::fill(reg, reg + m, kUnassigned);
  free_regs.clear();
  std::uint32_t count = 0;
  const auto take = [&]() -> std::uint32_t {
    if (free_regs.empty()) return count++;
    const std::uint32_t r = free_regs.back();
    free_regs.pop_back();
    return r;
  };
  reg[m - 1] = take();  // the root: live at the end
  for (std::size_t k = code_size_; k-- > 0;) {
    RegInstr& r = code_[k];
    FREP_ASSERT(r.out < m, "register code is not in SSA form");
    std::uint32_t out = reg[r.out];
    if (out == kUnassigned) out = take();  // a dead value: any free register
    free_regs.push_back(out);
    r.out = out;
    const int ar = op_arity(r.op);
    if (ar >= 1 && !(r.mode & RegInstr::kImmA)) {
      std::uint32_t& ra = reg[r.a];
      if (ra == kUnassigned) ra = take();
      r.a = ra;
    }
    if (ar >= 2 && !(r.mode & RegInstr::kImmB)) {
      std::uint32_t& rb = reg[r.b];
      if (rb == kUnassigned) rb = take();
      r.b = rb;
    }
  }
  num_regs_ = count;
  root_reg_ = reg[m - 1];
}

}  // namespace frep
