#include "host/common/process_memory.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace hmp {
namespace {

// The truth by construction: pages this test maps and touches are resident, and unmapping them gives
// them back. 64 MiB is far above what anything else in the process does meanwhile.
TEST(ProcessMemory, FollowsPagesTouchedAndGivenBack) {
  constexpr std::size_t kBytes = 64u << 20;
  const std::optional<std::uint64_t> before = resident_set_kib();
  ASSERT_TRUE(before.has_value());
  EXPECT_GT(*before, 0u);
  void* block = mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(block, MAP_FAILED);
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  for (std::size_t i = 0; i < kBytes; i += page) static_cast<volatile char*>(block)[i] = 1;
  const std::optional<std::uint64_t> touched = resident_set_kib();
  ASSERT_TRUE(touched.has_value());
  EXPECT_GE(*touched, *before + (kBytes >> 10) * 95 / 100);
  munmap(block, kBytes);
  const std::optional<std::uint64_t> after = resident_set_kib();
  ASSERT_TRUE(after.has_value());
  EXPECT_LE(*after, *touched - (kBytes >> 10) * 95 / 100);
}

}  // namespace
}  // namespace hmp
