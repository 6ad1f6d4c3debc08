#pragma once
// What every command shares around running: exit codes, the version, and turning an exception into the
// one-line message of design §3.
#include <functional>
#include <string>

namespace hmp::cli {

// Exit codes (design §3).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // a run that failed for a reason other than bad input
inline constexpr int kExitBadInput = 2;  // bad file, bad option: one-line message on stderr

std::string version_string();  // "hmp 0.1.0 (protocol 3)", " from <git describe>" when built from a clone

// Runs the action; BadInput → "error: …" on stderr and kExitBadInput, any other exception → "error: …"
// and kExitFailure.
int run_command(const std::function<int()>& action);

}  // namespace hmp::cli
