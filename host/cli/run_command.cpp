#include "host/cli/run_command.hpp"

#include <cstdio>
#include <exception>
#include <string>

#include "host/common/error.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::cli {

std::string version_string() {
  return "hmp 0.1.0 (protocol " + std::to_string(protocol::kProtocolVersion) + ")";
}

int run_command(const std::function<int()>& action) {
  try {
    return action();
  } catch (const hmp::BadInput& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitFailure;
  }
}

}  // namespace hmp::cli
