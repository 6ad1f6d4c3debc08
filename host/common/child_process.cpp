#include "host/common/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

extern char** environ;

namespace hmp {

pid_t start_child(const ChildSetup& setup, std::string& error) {
  if (setup.argv.empty()) {
    error = "no program";
    return -1;
  }
  std::vector<char*> argv;
  for (const std::string& a : setup.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!setup.cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, setup.cwd.c_str());
  if (!setup.stdin_path.empty()) posix_spawn_file_actions_addopen(&actions, 0, setup.stdin_path.c_str(), O_RDONLY, 0);
  const int out = O_WRONLY | O_CREAT | O_TRUNC;
  if (!setup.stdout_path.empty()) posix_spawn_file_actions_addopen(&actions, 1, setup.stdout_path.c_str(), out, 0644);
  if (!setup.stderr_path.empty()) posix_spawn_file_actions_addopen(&actions, 2, setup.stderr_path.c_str(), out, 0644);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  if (setup.own_process_group) {
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
  }
  pid_t pid = -1;
  const int err = setup.program.empty()
                      ? ::posix_spawnp(&pid, argv[0], &actions, &attr, argv.data(), environ)
                      : ::posix_spawn(&pid, setup.program.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    error = std::strerror(err);
    return -1;
  }
  return pid;
}

int wait_child(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void stop_child(pid_t pid, std::chrono::milliseconds grace) {
  ::kill(pid, SIGTERM);
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace hmp
