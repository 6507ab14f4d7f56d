#include "frep/io/load.hpp"

#include "frep/io/atomic_file.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/vm.hpp"

namespace frep {

Model load_expression(const std::string& path) {
  const std::string bytes = read_file(path);
  if (is_frep_file(bytes)) return parse_frep(bytes, path);
  return parse_vm(bytes, path);
}

}  // namespace frep
