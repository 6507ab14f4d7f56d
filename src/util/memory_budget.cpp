#include "frep/util/memory_budget.hpp"

#include <unistd.h>

#include <cstdio>

#include "frep/error.hpp"

namespace frep {

std::uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(size) : 0;
}

void require_memory(std::uint64_t count, std::uint64_t bytes_each, const std::string& job, const std::string& advice) {
  // Saturating: a count of 2^62 points must be refused, not wrap to a small product.
  std::uint64_t bytes;
  if (__builtin_mul_overflow(count, bytes_each, &bytes)) bytes = UINT64_MAX;
  const std::uint64_t have = physical_memory_bytes();
  if (have == 0 || bytes <= have) return;
  char buf[160];
  std::snprintf(buf, sizeof buf, " needs about %.1f GB of memory, more than this machine's %.1f GB: ",
                static_cast<double>(bytes) / 1e9, static_cast<double>(have) / 1e9);
  throw InputError("", 0, job + buf + advice);
}

}  // namespace frep
