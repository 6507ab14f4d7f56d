// libFuzzer entry for the JIT backend: the bytes decode into a tape over every opcode and points
// at special values (jit_differential.hpp); the JIT's results in every instruction set this CPU
// runs must equal the interpreter's bit for bit. A mismatch aborts with what differs.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "jit_differential.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const frep::fuzz::DiffCase c = frep::fuzz::decode_case(data, size);
  for (frep::JitIsa isa : {frep::JitIsa::Avx2, frep::JitIsa::Avx512}) {
    if (!frep::jit_supported(isa)) continue;
    const std::string diff = frep::fuzz::check_case(c, isa);
    if (!diff.empty()) {
      std::fprintf(stderr, "JIT (%s) differs from the interpreter: %s\n", isa == frep::JitIsa::Avx2 ? "AVX2" : "AVX-512",
                   diff.c_str());
      std::abort();
    }
  }
  return 0;
}
