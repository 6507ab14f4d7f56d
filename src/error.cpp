#include "frep/error.hpp"

namespace frep {
namespace {
std::string located(const std::string& file, std::uint64_t line, std::uint64_t offset,
                    const std::string& msg) {
  std::string where = file.empty() ? std::string("<input>") : file;
  if (line > 0) where += ":" + std::to_string(line);
  else if (offset > 0) where += ": byte " + std::to_string(offset);
  return where + ": " + msg;
}
}  // namespace

InputError::InputError(std::string file, std::uint64_t line, std::string message,
                       std::uint64_t byte_offset)
    : std::runtime_error(located(file, line, byte_offset, message)),
      file_(std::move(file)),
      line_(line),
      offset_(byte_offset),
      detail_(std::move(message)) {}

void assert_fail(const char* expr, const char* file, int line, const std::string& msg) {
  std::string text = std::string(file) + ":" + std::to_string(line) + ": internal error: assertion `" +
                     expr + "` failed";
  if (!msg.empty()) text += ": " + msg;
  throw InternalError(text);
}

}  // namespace frep
