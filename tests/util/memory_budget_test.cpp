#include "frep/util/memory_budget.hpp"

#include <gtest/gtest.h>

#include "frep/error.hpp"

namespace frep {
namespace {

TEST(MemoryBudget, RefusesOnlyWhatTheMachineCannotHold) {
  const std::uint64_t have = physical_memory_bytes();
  ASSERT_GT(have, 0u) << "sysconf gives no physical memory size";
  EXPECT_NO_THROW(require_memory(0, 16, "nothing", "-"));
  EXPECT_NO_THROW(require_memory(have / 2, 1, "half", "-"));
  try {
    require_memory(have + (have >> 2), 1, "a huge job", "do less");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("a huge job needs about "), std::string::npos) << m;
    EXPECT_NE(m.find("GB of memory, more than this machine's "), std::string::npos) << m;
    EXPECT_NE(m.find("GB: do less"), std::string::npos) << m;
  }
  // A product that wraps (2^62 points of 16 bytes is 0 modulo 2^64) is still refused.
  EXPECT_THROW(require_memory(std::uint64_t(1) << 62, 16, "2^62 points", "-"), InputError);
  EXPECT_THROW(require_memory(UINT64_MAX, UINT64_MAX, "everything", "-"), InputError);
}

}  // namespace
}  // namespace frep
