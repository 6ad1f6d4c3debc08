#pragma once
// Finding hmp's window on the tests' private X display and typing into it with X key events (xdotool),
// as a keyboard would.
#include <chrono>
#include <string>
#include <thread>

#include "play_harness.hpp"

namespace hmp::test {

// The X window whose name matches `name` (a regular expression: escape [ and ]), waiting up to 30 s; ""
// if none came.
inline std::string window_named(const std::string& name) {
  for (int i = 0; i < 300; ++i) {
    const CommandResult r = run_command("xdotool search --name '" + name + "'");
    if (r.status == 0 && !r.out.empty()) return r.out.substr(0, r.out.find('\n'));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return "";
}

// Types `keys` into window `id` as X key events: Enter is Return, the rest their own key.
inline void type_into(const std::string& id, const std::string& keys) {
  run_command("xdotool windowfocus --sync " + id);
  for (const char k : keys) {
    run_command("xdotool key " + (k == '\n' ? std::string("Return") : std::string(1, k)));
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
}

}  // namespace hmp::test
