#pragma once
// Boots the qemu-an386 firmware image for a test the way a host-side launcher does
// (boards/qemu-an386/README.md, "Host link"):
//   - the test listens on a unix-domain socket in a private temporary directory and QEMU connects to it
//     as UART0's chardev (`-chardev socket,path=…` without server=on): the connection exists before the
//     guest runs its first instruction, with no polling for a socket file and no pty to parse;
//   - the accepted socket becomes a transport::SerialTransport (framed 64-byte reports);
//   - semihosting output (the firmware's log, summary and optional trace) goes to a file, read afterwards.
// Also parses that output: the per-tick trace and the summary counters.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "host/transport/qemu_device.hpp"
#include "host/transport/serial_transport.hpp"
#include "shared/protocol/protocol.hpp"

extern char** environ;

namespace hmp::test {

// The firmware image: $HMP_QEMU_ELF if set (e.g. another cross tree), else the CMake cache variable.
inline std::string qemu_image_path() {
  if (const char* env = std::getenv("HMP_QEMU_ELF"); env != nullptr && *env != '\0') return env;
#ifdef HMP_QEMU_ELF
  return HMP_QEMU_ELF;
#else
  return {};
#endif
}

// Why a QEMU test cannot run here (for GTEST_SKIP), or empty when the image and the emulator are there.
inline std::string qemu_missing() {
  const std::string image = qemu_image_path();
  if (image.empty() || !std::filesystem::exists(image)) {
    return "no firmware image at '" + image + "' (build the qemu-an386 preset)";
  }
  if (std::system((transport::qemu_emulator() + " --version >/dev/null 2>&1").c_str()) != 0)
    return transport::qemu_emulator() + " not installed";
  return {};
}

class QemuFirmware {
 public:
  // Starts QEMU with `append` as the image's command line (its options). Throws std::runtime_error.
  QemuFirmware(const std::string& image, const std::string& append) {
    char dir_template[] = "/tmp/hmp-qemu-XXXXXX";
    if (::mkdtemp(dir_template) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = dir_template;
    const std::string socket_path = dir_ + "/uart0.sock";
    log_path_ = dir_ + "/semihosting.log";

    listen_fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, socket_path.c_str(), sizeof addr.sun_path - 1);
    if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listen_fd_, 1) != 0) {
      throw std::runtime_error("cannot listen on " + socket_path + ": " + std::strerror(errno));
    }

    const std::vector<std::string> args = {transport::qemu_emulator(), "-M", "mps2-an386", "-nographic", "-monitor",
                                           "none", "-semihosting-config", "enable=on,target=native",
                                           // One instruction = 1 ns of virtual time; while the guest sleeps in wfi,
                                           // virtual time follows real time (sleep=on, the default), so the firmware
                                           // ticks at its real rate and the host can keep up with it.
                                           "-icount", "shift=0", "-chardev", "socket,id=uart0,path=" + socket_path,
                                           "-serial", "chardev:uart0", "-kernel", image, "-append", append};
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::posix_spawnp(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (err != 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(err));

    pollfd p{listen_fd_, POLLIN, 0};
    if (::poll(&p, 1, 20000) != 1) throw std::runtime_error("QEMU did not connect to the UART socket: " + log_text());
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) throw std::runtime_error(std::string("accept: ") + std::strerror(errno));
    raw_fd_ = ::dup(fd);
    link_ = transport::SerialTransport::adopt(fd, "qemu:uart0");
  }

  ~QemuFirmware() {
    if (link_) link_->close();
    if (pid_ > 0 && !exit_status_) {
      ::kill(pid_, SIGKILL);  // only the process this object started
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
    if (raw_fd_ >= 0) ::close(raw_fd_);
    if (listen_fd_ >= 0) ::close(listen_fd_);
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  QemuFirmware(const QemuFirmware&) = delete;
  QemuFirmware& operator=(const QemuFirmware&) = delete;

  transport::SerialTransport& link() { return *link_; }
  // The same socket, for bytes that must bypass the transport's framing (deliberately broken frames).
  int raw_fd() const { return raw_fd_; }

  // Waits for QEMU to exit; its exit status (the image's semihosting exit code), nullopt on timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!exit_status_) {
      int status = 0;
      const pid_t r = ::waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (std::chrono::steady_clock::now() > deadline) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return exit_status_;
  }

  std::string log_text() const {
    std::ifstream in(log_path_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

 private:
  std::string dir_, log_path_;
  int listen_fd_ = -1, raw_fd_ = -1;
  pid_t pid_ = -1;
  std::optional<int> exit_status_;
  std::unique_ptr<transport::SerialTransport> link_;
};

// What the firmware wrote on its semihosting console with the `trace` option (boards/qemu-an386/
// output_trace.hpp) and at exit (the summary lines).
struct FirmwareRun {
  struct Received {
    std::uint32_t tick = 0;  // the core's tick counter when the report was handed over
    std::array<std::uint8_t, protocol::kReportSize> bytes{};
  };
  std::vector<float> outputs;                     // outputs[i] is the output of tick i + 1
  std::vector<Received> reports;                  // in arrival order
  std::map<std::string, std::uint64_t> counters;  // "link.crc_errors", "core.late", "trace.dropped", …
  std::vector<std::string> log;                   // "log: " lines of the core
  std::vector<std::string> problems;              // trace lines that did not parse or left a gap
};

inline FirmwareRun parse_firmware_log(const std::string& text) {
  FirmwareRun run;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "y") {
      std::uint64_t tick = 0;
      words >> tick;
      if (!words || tick != run.outputs.size() + 1) {
        run.problems.push_back("output line out of order: " + line);
        continue;
      }
      std::string bits;
      while (words >> bits) {
        const auto v = static_cast<std::uint32_t>(std::stoul(bits, nullptr, 16));
        float f;
        std::memcpy(&f, &v, sizeof f);
        run.outputs.push_back(f);
      }
    } else if (kind == "rx") {
      FirmwareRun::Received r;
      std::string hex;
      words >> r.tick >> hex;
      if (!words || hex.size() != 2 * protocol::kReportSize) {
        run.problems.push_back("bad report line: " + line);
        continue;
      }
      for (std::size_t i = 0; i < protocol::kReportSize; ++i) {
        r.bytes[i] = static_cast<std::uint8_t>(std::stoul(hex.substr(2 * i, 2), nullptr, 16));
      }
      run.reports.push_back(r);
    } else if (kind == "link:" || kind == "core:" || kind == "trace:") {
      const std::string prefix = kind.substr(0, kind.size() - 1) + ".";
      std::string field;
      while (words >> field) {
        const auto eq = field.find('=');
        if (eq == std::string::npos) continue;
        run.counters[prefix + field.substr(0, eq)] = std::stoull(field.substr(eq + 1), nullptr, 0);
      }
    } else if (kind == "log:") {
      run.log.push_back(line);
    }
  }
  return run;
}

}  // namespace hmp::test
