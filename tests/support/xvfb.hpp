#pragma once
// A private X display for tests of windows: starts Xvfb on a free display number (24-bit colour, no
// network), points DISPLAY at it, and stops it when done. Mesa's llvmpipe draws OpenGL on it, as on a
// machine without a GPU.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

namespace hmp::test {

class Xvfb {
 public:
  Xvfb() {
    for (int n = 90; n < 120 && pid_ <= 0; ++n) {
      const std::string socket = "/tmp/.X11-unix/X" + std::to_string(n);
      const std::string lock = "/tmp/.X" + std::to_string(n) + "-lock";
      struct stat st {};
      if (::stat(socket.c_str(), &st) == 0 || ::stat(lock.c_str(), &st) == 0) continue;
      const std::string display = ":" + std::to_string(n);
      const pid_t pid = ::fork();
      if (pid == 0) {
        ::execlp("Xvfb", "Xvfb", display.c_str(), "-screen", "0", "1600x1000x24", "-nolisten", "tcp", "-noreset",
                 static_cast<char*>(nullptr));
        _exit(127);
      }
      for (int i = 0; i < 100; ++i) {  // up to 5 s for the socket
        if (::stat(socket.c_str(), &st) == 0) {
          pid_ = pid;
          display_ = display;
          break;
        }
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) break;  // it died (display taken, or no Xvfb)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (pid_ <= 0 && pid > 0) {
        ::kill(pid, SIGTERM);
        ::waitpid(pid, nullptr, 0);
      }
    }
    if (pid_ > 0) ::setenv("DISPLAY", display_.c_str(), 1);
  }
  ~Xvfb() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;

  bool running() const { return pid_ > 0; }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

// The process's one private display, started on first use and stopped at exit. Tests share it: SDL keeps
// its video subsystem (and its X connection) for the whole process, so a display stopped after one test
// and started again for the next would leave SDL talking to a dead server.
inline Xvfb& xvfb() {
  static Xvfb display;
  if (display.running()) ::setenv("DISPLAY", display.display().c_str(), 1);  // a test may have unset it
  return display;
}

}  // namespace hmp::test
