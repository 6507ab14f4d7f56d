#include "frep/util/memory_budget.hpp"

#include <gtest/gtest.h>

#include "frep/error.hpp"

namespace frep {
namespace {

TEST(MemoryBudget, RefusesOnlyWhatTheMachineCannotHold) {
  const std::uint64_t have = physical_memory_bytes();
  ASSERT_GT(have, 0u) << "sysconf gives no physical memory size";
  EXPECT_NO_THROW(require_memory(0, "nothing", "-"));
  EXPECT_NO_THROW(require_memory(have / 2, "half", "-"));
  try {
    require_memory(have + (have >> 2), "a huge job", "do less");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("a huge job needs about "), std::string::npos) << m;
    EXPECT_NE(m.find("GB of memory, more than this machine's "), std::string::npos) << m;
    EXPECT_NE(m.find("GB: do less"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace frep
