#include <fmt/core.h>

#include <array>

#include "commands.hpp"
#include "input.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/jit.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/oracle.hpp"
#include "frep/script/load.hpp"

namespace frep::cli {

void register_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print node counts by opcode, variables used and tape length");
  auto file = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, kFieldInputHelp)->required();
  cmd->callback([file] {
    const Model m = load_input(*file);
    const std::vector<NodeId> nodes = reachable_nodes(*m.graph, m.root);
    std::array<std::size_t, kEngineOpCount> counts{};
    for (NodeId id : nodes) ++counts[static_cast<int>(m.graph->node(id).op)];
    const Tape tape = Tape::compile(*m.graph, m.root);
    fmt::print("file: {}\n", *file);
    fmt::print("nodes: {} (after hash-consing and folding)\n", nodes.size());
    std::string vars;
    if (tape.vars_used() & 1) vars += "x ";
    if (tape.vars_used() & 2) vars += "y ";
    if (tape.vars_used() & 4) vars += "z ";
    fmt::print("variables: {}\n", vars.empty() ? "none" : vars.substr(0, vars.size() - 1));
    fmt::print("tape: {} instructions, {} registers, {} choices (min/max/and/or)\n", tape.code().size(),
               tape.num_registers(), tape.choice_count());
    // The evaluator this run (and any other without FREP_BACKEND changed) uses.
    if (std::string(default_backend().name()) == "jit" && jit_supported())
      fmt::print("evaluator: jit ({} machine code for tapes evaluated on {}+ points or in {}+ interval passes; "
                 "FREP_BACKEND=interp: the interpreter only)\n",
                 jit_supported(JitIsa::Avx512) ? "AVX-512" : "AVX2", JitOptions{}.compile_after_points,
                 JitOptions{}.compile_after_interval_passes);
    else
      fmt::print("evaluator: interpreter ({} SIMD)\n", BatchEvaluator::target_name());
    if (m.info.lipschitz > 0)
      fmt::print("lipschitz: {:g} (|f(p) - f(q)| <= {:g} |p - q|)\n", m.info.lipschitz, m.info.lipschitz);
    if (!m.info.bounds.empty()) {
      const Box3& b = m.info.bounds;
      fmt::print("bounds: {:.9g}, {:.9g}, {:.9g} .. {:.9g}, {:.9g}, {:.9g} (holds every point where it is negative)\n",
                 b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    }
    if (m.info.growth == Growth::Distance)
      fmt::print("growth: distance (at least the distance to the inside, outside it: offsets grow the bounds)\n");
    else if (m.info.growth == Growth::Box)
      fmt::print("growth: box (where it is below t >= 0 lies within t of the bounds: offsets grow them)\n");
    fmt::print("opcodes:\n");
    for (int op = 0; op < kEngineOpCount; ++op)
      if (counts[op]) fmt::print("  {:<8} {}\n", op_name(static_cast<Op>(op)), counts[op]);
    if (counts[static_cast<int>(Op::Oracle)]) {
      // Leaves computed by code: what each stands for (its closed form is what files get).
      fmt::print("oracles:\n");
      for (NodeId id : nodes)
        if (m.graph->node(id).op == Op::Oracle) fmt::print("  {}\n", m.graph->oracle_of(m.graph->node(id)).describe());
    }
  });
}

}  // namespace frep::cli
