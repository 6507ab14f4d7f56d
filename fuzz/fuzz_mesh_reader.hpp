// One libFuzzer entry per reader: any InputError is an expected outcome, everything else
// (crash, sanitizer report, other exception, hang, huge allocation) is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"

#define FREP_MESH_FUZZER(reader)                                                          \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {     \
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);              \
    try {                                                                                 \
      frep::TriMesh m = reader(bytes, "fuzz");                                            \
      /* A successfully read mesh must be internally consistent. */                      \
      for (const frep::Triangle& t : m.triangles)                                         \
        for (std::uint32_t v : t)                                                         \
          if (v >= m.vertices.size()) __builtin_trap();                                   \
      if (m.origins.size() != m.triangles.size()) __builtin_trap();                       \
      frep::weld(m);                                                                      \
    } catch (const frep::InputError&) {                                                   \
    }                                                                                     \
    return 0;                                                                             \
  }
