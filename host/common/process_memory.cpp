#include "host/common/process_memory.hpp"

#include <cstdio>
#include <cstring>

namespace hmp {

std::optional<std::uint64_t> resident_set_kib() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return std::nullopt;
  std::optional<std::uint64_t> kib;
  char line[256];
  while (std::fgets(line, sizeof line, f) != nullptr) {
    unsigned long long value = 0;
    if (std::strncmp(line, "VmRSS:", 6) == 0 && std::sscanf(line + 6, "%llu", &value) == 1) {
      kib = value;
      break;
    }
  }
  std::fclose(f);
  return kib;
}

}  // namespace hmp
