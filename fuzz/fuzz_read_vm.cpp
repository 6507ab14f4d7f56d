// libFuzzer entry for the .vm reader: InputError is an expected outcome; anything else (crash,
// sanitizer report, other exception, hang) is a finding. A model that loads must compile and
// evaluate.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/io/vm.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const frep::Model m = frep::parse_vm(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    const frep::Tape t = frep::Tape::compile(*m.graph, m.root);
    frep::PointEvaluator ev;
    ev.eval(t, 0.5f, -0.25f, 2.0f);
  } catch (const frep::InputError&) {
  }
  return 0;
}
