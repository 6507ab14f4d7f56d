#include "frep/script/save.hpp"

#include "frep/error.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/script/rhai.hpp"
#include "frep/io/vm.hpp"
#include "frep/util/atomic_file.hpp"
#include "frep/util/text_scan.hpp"

namespace frep {
namespace {

enum class Format { Vm, Frep, Rhai };

Format format_of(const std::string& path) {
  const auto dot = path.rfind('.');
  const std::string_view ext = dot == std::string::npos ? std::string_view{} : std::string_view(path).substr(dot + 1);
  if (detail::iequals(ext, "vm")) return Format::Vm;
  if (detail::iequals(ext, "frep")) return Format::Frep;
  if (detail::iequals(ext, "rhai")) return Format::Rhai;
  if (is_device(path)) return Format::Frep;  // /dev/null: frep's own format, written in place
  throw InputError(path, 0, "unknown expression format: use a .vm, .rhai or .frep file name");
}

}  // namespace

void check_expression_path(const std::string& path) { format_of(path); }

void save_expression(const std::string& path, const Graph& g, NodeId root, const FieldInfo& info,
                     const FrepOracleCodec* oracles) {
  switch (format_of(path)) {
    case Format::Vm: return save_vm(path, g, root, info);
    case Format::Frep: return save_frep(path, g, root, info, oracles);
    case Format::Rhai: return save_rhai(path, g, root, info);
  }
}

void save_expression(const std::string& path, const Model& m, const FrepOracleCodec* oracles) {
  save_expression(path, *m.graph, m.root, m.info, oracles);
}

}  // namespace frep
