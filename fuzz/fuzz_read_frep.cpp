// libFuzzer entry for the .frep reader: InputError is an expected outcome; anything else (crash,
// sanitizer report, other exception, hang, huge allocation) is a finding. A model that loads must
// compile, evaluate and serialize back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/io/frep_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const frep::Model m = frep::parse_frep(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    const frep::Tape t = frep::Tape::compile(*m.graph, m.root);
    frep::PointEvaluator ev;
    ev.eval(t, 0.5f, -0.25f, 2.0f);
    const frep::Model again = frep::parse_frep(frep::serialize_frep(*m.graph, m.root), "again");
    if (frep::reachable_nodes(*again.graph, again.root).size() != frep::reachable_nodes(*m.graph, m.root).size())
      __builtin_trap();
  } catch (const frep::InputError&) {
  }
  return 0;
}
