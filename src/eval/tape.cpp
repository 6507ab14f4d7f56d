#include "frep/eval/tape.hpp"

#include <bit>

#include "frep/error.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {

Tape Tape::compile(const Graph& g, NodeId root) {
  Tape t;
  const std::vector<NodeId> order = reachable_nodes(g, root);
  std::vector<std::uint32_t> index(root + 1, 0);
  t.ssa_.reserve(order.size());
  for (NodeId id : order) {
    const Node& n = g.node(id);
    SsaInstr ins{n.op, 0, 0, n.value};
    if (n.a != kNoNode) ins.a = index[n.a];
    if (n.b != kNoNode) ins.b = index[n.b];
    index[id] = static_cast<std::uint32_t>(t.ssa_.size());
    t.ssa_.push_back(ins);
  }
  t.finish();
  return t;
}

Tape Tape::from_ssa(std::vector<SsaInstr> ssa) {
  FREP_ASSERT(!ssa.empty(), "empty tape");
  Tape t;
  std::vector<std::uint32_t> remap(ssa.size());
  for (std::size_t i = 0; i < ssa.size(); ++i) {
    SsaInstr ins = ssa[i];
    const int ar = op_arity(ins.op);
    if (ar >= 1) {
      FREP_ASSERT(ins.a < i, "argument after its use");
      ins.a = remap[ins.a];
    }
    if (ar >= 2) {
      FREP_ASSERT(ins.b < i, "argument after its use");
      ins.b = remap[ins.b];
    }
    remap[i] = t.emit(ins);
  }
  // The root may have folded into an earlier instruction: make it last.
  if (remap.back() + 1 != t.ssa_.size()) t.ssa_.push_back(t.ssa_[remap.back()]);
  t.finish();
  return t;
}

std::uint32_t Tape::emit(const SsaInstr& ins) {
  const int ar = op_arity(ins.op);
  if (ar >= 1) {
    const SsaInstr& a = ssa_[ins.a];
    if (a.op == Op::Const) {
      if (ar == 1) {
        ssa_.push_back({Op::Const, 0, 0, op_eval<float>(ins.op, a.value, 0.0f)});
        return static_cast<std::uint32_t>(ssa_.size() - 1);
      }
      const SsaInstr& b = ssa_[ins.b];
      if (b.op == Op::Const) {
        ssa_.push_back({Op::Const, 0, 0, op_eval<float>(ins.op, a.value, b.value)});
        return static_cast<std::uint32_t>(ssa_.size() - 1);
      }
      if (ins.op == Op::And) return a.value == 0.0f ? ins.a : ins.b;
      if (ins.op == Op::Or) return a.value != 0.0f ? ins.a : ins.b;
    }
  }
  ssa_.push_back(ins);
  return static_cast<std::uint32_t>(ssa_.size() - 1);
}

void Tape::finish() {
  const std::size_t n = ssa_.size();
  FREP_ASSERT(n > 0, "empty tape");
  // Drop dead instructions (left behind by folding) so the root is last and every value is used.
  std::vector<std::uint32_t>& live = scratch_a_;
  live.assign(n, 0);
  live[n - 1] = 1;
  std::size_t dead = 0;
  for (std::size_t i = n; i-- > 0;) {
    if (!live[i]) {
      ++dead;
      continue;
    }
    const int ar = op_arity(ssa_[i].op);
    if (ar >= 1) live[ssa_[i].a] = 1;
    if (ar >= 2) live[ssa_[i].b] = 1;
  }
  if (dead) {
    std::vector<std::uint32_t>& remap = scratch_b_;
    remap.resize(n);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!live[i]) continue;
      SsaInstr ins = ssa_[i];
      const int ar = op_arity(ins.op);
      if (ar >= 1) ins.a = remap[ins.a];
      if (ar >= 2) ins.b = remap[ins.b];
      remap[i] = static_cast<std::uint32_t>(k);
      ssa_[k++] = ins;
    }
    ssa_.resize(k);
  }

  // Counts, and the last use of every value (the root is never freed).
  const std::size_t m = ssa_.size();
  choices_ = 0;
  vars_ = 0;
  std::vector<std::uint32_t>& last_use = scratch_a_;
  last_use.assign(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const SsaInstr& ins = ssa_[i];
    if (op_is_choice(ins.op)) ++choices_;
    if (ins.op == Op::VarX) vars_ |= 1;
    if (ins.op == Op::VarY) vars_ |= 2;
    if (ins.op == Op::VarZ) vars_ |= 4;
    const int ar = op_arity(ins.op);
    if (ar >= 1) last_use[ins.a] = static_cast<std::uint32_t>(i);
    if (ar >= 2) last_use[ins.b] = static_cast<std::uint32_t>(i);
  }
  last_use[m - 1] = static_cast<std::uint32_t>(m);

  // Linear-scan register allocation: a register is free again after its value's last use, and
  // an instruction may write the register one of its arguments just freed (evaluators read
  // arguments before writing, lane by lane).
  std::vector<std::uint32_t>& reg_of = scratch_b_;
  reg_of.assign(m, 0);
  std::vector<std::uint32_t> free_regs;
  code_.clear();
  num_regs_ = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const SsaInstr& ins = ssa_[i];
    if (ins.op == Op::Const && i + 1 != m) continue;  // an immediate of its users
    RegInstr r;
    r.op = ins.op;
    const int ar = op_arity(ins.op);
    if (ins.op == Op::Const) r.imm = ins.value;
    auto bind = [&](std::uint32_t arg, std::uint32_t& slot, std::uint8_t imm_bit) {
      if (ssa_[arg].op == Op::Const) {
        FREP_ASSERT(!(r.mode & (RegInstr::kImmA | RegInstr::kImmB)), "two immediate arguments");
        r.mode |= imm_bit;
        r.imm = ssa_[arg].value;
      } else {
        slot = reg_of[arg];
      }
    };
    if (ar >= 1) bind(ins.a, r.a, RegInstr::kImmA);
    if (ar >= 2) bind(ins.b, r.b, RegInstr::kImmB);
    if (ar >= 1 && ssa_[ins.a].op != Op::Const && last_use[ins.a] == i) free_regs.push_back(reg_of[ins.a]);
    if (ar >= 2 && ins.b != ins.a && ssa_[ins.b].op != Op::Const && last_use[ins.b] == i)
      free_regs.push_back(reg_of[ins.b]);
    std::uint32_t out;
    if (free_regs.empty()) {
      out = num_regs_++;
    } else {
      out = free_regs.back();
      free_regs.pop_back();
    }
    reg_of[i] = out;
    r.out = out;
    code_.push_back(r);
  }
  root_reg_ = reg_of[m - 1];
}

namespace {
bool foldable(Op op, const Interval& v) {
  if (!(v.lo == v.hi)) return false;  // also false for unknown
  if (v.lo != 0.0f) return true;
  // A zero interval may hide -0 versus +0; only these ops produce an exact +0.
  return op == Op::Compare || op == Op::Not;
}
}  // namespace

void Tape::simplify(const std::vector<Interval>& values, const std::vector<Choice>& choices, Tape& out) const {
  FREP_ASSERT(&out != this, "simplify into itself");
  const std::size_t n = ssa_.size();
  FREP_ASSERT(values.size() >= n && choices.size() >= n, "interval results do not match the tape");
  // Backward: decide what each live instruction becomes.
  enum : std::uint32_t { kDead = 0, kKeep = 1, kConst = 2, kLeft = 3, kRight = 4, kLive = 5 };
  std::vector<std::uint32_t>& state = out.scratch_a_;
  state.assign(n, kDead);
  state[n - 1] = kLive;
  for (std::size_t i = n; i-- > 0;) {
    if (state[i] == kDead) continue;
    const SsaInstr& ins = ssa_[i];
    const int ar = op_arity(ins.op);
    if (ar > 0 && foldable(ins.op, values[i])) {
      state[i] = kConst;
      continue;
    }
    if (op_is_choice(ins.op) && choices[i] != Choice::Both) {
      const bool left = choices[i] == Choice::Left;
      state[i] = left ? kLeft : kRight;
      const std::uint32_t arg = left ? ins.a : ins.b;
      if (state[arg] == kDead) state[arg] = kLive;
      continue;
    }
    state[i] = kKeep;
    if (ar >= 1 && state[ins.a] == kDead) state[ins.a] = kLive;
    if (ar >= 2 && state[ins.b] == kDead) state[ins.b] = kLive;
  }
  // Forward: emit with remapped arguments.
  std::vector<std::uint32_t>& remap = out.scratch_b_;
  remap.resize(n);
  out.ssa_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const SsaInstr& ins = ssa_[i];
    switch (state[i]) {
      case kDead:
        break;
      case kConst:
        out.ssa_.push_back({Op::Const, 0, 0, values[i].lo});
        remap[i] = static_cast<std::uint32_t>(out.ssa_.size() - 1);
        break;
      case kLeft:
        remap[i] = remap[ins.a];
        break;
      case kRight:
        remap[i] = remap[ins.b];
        break;
      default: {
        SsaInstr c = ins;
        const int ar = op_arity(ins.op);
        if (ar >= 1) c.a = remap[ins.a];
        if (ar >= 2) c.b = remap[ins.b];
        remap[i] = out.emit(c);
      }
    }
  }
  if (remap[n - 1] + 1 != out.ssa_.size()) {
    // The root is an earlier value (a chosen side or a folded argument): repeat it last, as a
    // copy of its instruction, and let finish() drop what became dead.
    out.ssa_.push_back(out.ssa_[remap[n - 1]]);
  }
  out.finish();
}

Tape Tape::simplified(const std::vector<Interval>& values, const std::vector<Choice>& choices) const {
  Tape out;
  simplify(values, choices, out);
  return out;
}

}  // namespace frep
