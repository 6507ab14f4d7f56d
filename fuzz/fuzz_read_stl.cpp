#include "fuzz_mesh_reader.hpp"

FREP_MESH_FUZZER(frep::read_stl)
