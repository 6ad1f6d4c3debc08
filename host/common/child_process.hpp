#pragma once
// Starting another program: the tools `hmp flash` runs (cmake, dfu-util, st-flash, openocd, sudo) and
// the emulator of `--device qemu`. One way for both: posix_spawn, the streams and the process group the
// caller asks for, and waiting or stopping by the child's own id.
#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace hmp {

struct ChildSetup {
  std::vector<std::string> argv;                     // argv[0] is the program's name as it sees it
  std::string program;                               // the file run; "" looks argv[0] up in PATH
  std::string cwd;                                   // "" the caller's
  std::string stdin_path, stdout_path, stderr_path;  // "" inherit; stdout and stderr are truncated
  bool own_process_group = false;                    // the terminal's Ctrl-C is not sent to it (the caller stops it)
};

// The child's process id, or −1 with `error` saying why it could not start.
pid_t start_child(const ChildSetup& setup, std::string& error);
// Waits for the child to end: its exit code, or −1 when it was killed (or cannot be waited for).
int wait_child(pid_t pid);
// SIGTERM, and SIGKILL if it has not ended after `grace`; then reaped.
void stop_child(pid_t pid, std::chrono::milliseconds grace);

}  // namespace hmp
