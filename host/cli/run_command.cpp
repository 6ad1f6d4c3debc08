#include "host/cli/run_command.hpp"

#include <cstdio>
#include <exception>
#include <string>

#include "host/cli/git_describe.hpp"
#include "host/common/error.hpp"
#include "host/common/printable.hpp"
#include "host/common/install_layout.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::cli {

std::string version_string() {
  const std::string describe = HMP_GIT_DESCRIBE;  // "" outside a git clone
  // No comma: the study writes this into a CSV field.
  return "hmp " + install::version_text() + " (protocol " + std::to_string(protocol::kProtocolVersion) + ")" +
         (describe.empty() ? "" : " from " + describe);
}

int run_command(const std::function<int()>& action) {
  try {
    return action();
  } catch (const hmp::BadInput& e) {
    std::fprintf(stderr, "error: %s\n", terminal_line(e.what()).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", terminal_line(e.what()).c_str());
    return kExitFailure;
  }
}

}  // namespace hmp::cli
