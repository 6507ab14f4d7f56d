// Error types shared by every part of frep.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace frep {

// Bad input: a file or argument the user supplied. Carries where the problem is.
class InputError : public std::runtime_error {
 public:
  // `file` may be empty (in-memory input); `line` and `byte_offset` are 0 when unknown.
  InputError(std::string file, std::uint64_t line, std::string message, std::uint64_t byte_offset = 0);

  const std::string& file() const { return file_; }
  std::uint64_t line() const { return line_; }
  std::uint64_t byte_offset() const { return offset_; }
  // The message without the location prefix.
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  std::uint64_t line_;
  std::uint64_t offset_;
  std::string detail_;
};

// A violated internal invariant: a bug in frep, never the user's fault.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void assert_fail(const char* expr, const char* file, int line, const std::string& msg);

}  // namespace frep

// Internal invariant check, active in every build type; reports file:line.
#define FREP_ASSERT(cond, ...)                                                   \
  do {                                                                           \
    if (!(cond)) ::frep::assert_fail(#cond, __FILE__, __LINE__, std::string{__VA_ARGS__}); \
  } while (0)
