#include "host/cli/commands.hpp"

#include <cstdio>
#include <exception>

#include "host/common/error.hpp"

namespace hmp::cli {

std::string version_string() { return "hmp 0.1.0 (protocol 1)"; }

int Registry::run() const {
  if (!action_) return kExitBadInput;
  try {
    return action_();
  } catch (const hmp::BadInput& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitFailure;
  }
}

void register_all(CLI::App& app, Registry& registry) {
  register_info(app, registry);
  register_render(app, registry);
  register_tone(app, registry);
  register_devices(app, registry);
  register_play(app, registry);
  register_sim(app, registry);
}

}  // namespace hmp::cli
