#pragma once
// The memory this process holds in RAM (its resident set), as the kernel counts it: what a long run
// watches for growth.
#include <cstdint>
#include <optional>

namespace hmp {

// VmRSS of /proc/self/status in KiB; nullopt where it cannot be read (no /proc).
std::optional<std::uint64_t> resident_set_kib();

}  // namespace hmp
