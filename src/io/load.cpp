#include "frep/io/load.hpp"

#include "frep/io/vm.hpp"

namespace frep {

Model load_expression(const std::string& path) { return read_vm(path); }

}  // namespace frep
