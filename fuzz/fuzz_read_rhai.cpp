// libFuzzer entry for the Rhai reader: an InputError is an expected outcome; anything else
// (crash, sanitizer report, other exception, hang, huge allocation) is a finding. Small step
// and node limits keep runaway inputs fast; they exercise the same checks as the defaults.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frep/error.hpp"
#include "frep/script/rhai.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  frep::RhaiOptions options;
  options.max_steps = 100000;
  options.max_nodes = 100000;
  try {
    const frep::Model m = frep::parse_rhai(text, "fuzz", options);
    if (m.root >= m.graph->size()) __builtin_trap();  // a read model must be consistent
  } catch (const frep::InputError&) {
  }
  return 0;
}
