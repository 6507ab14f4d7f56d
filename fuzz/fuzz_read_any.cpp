#include "fuzz_mesh_reader.hpp"

namespace {
frep::TriMesh read_any(std::string_view bytes, const std::string& name) {
  return frep::read_mesh_from_memory(bytes, name);
}
}  // namespace

FREP_MESH_FUZZER(read_any)
