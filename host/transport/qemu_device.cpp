#include "host/transport/qemu_device.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "host/common/child_process.hpp"
#include "host/common/install_layout.hpp"
#include "host/transport/ether_transport.hpp"
#include "host/transport/serial_transport.hpp"

namespace hmp::transport {

namespace fs = std::filesystem;

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : "";
}

}  // namespace

std::string qemu_emulator() {
  const std::string chosen = env("QEMU_SYSTEM_ARM");
  return chosen.empty() ? "qemu-system-arm" : chosen;
}

std::string find_qemu_image() {
  if (const std::string e = env("HMP_QEMU_ELF"); !e.empty()) return e;
  const std::string name = install::image_file_name("qemu-an386", ".elf");
  std::error_code ec;
  // Run from a build tree: the source tree's qemu-an386 cross tree (preset qemu-an386). Installed: ours.
  if (const auto tree = install::source_tree()) {
    const fs::path built = *tree / "build" / "qemu-an386" / "boards" / "qemu-an386" / name;
    return fs::exists(built, ec) ? built.string() : std::string{};
  }
  const fs::path installed = install::installed_image("qemu-an386", ".elf");
  return fs::exists(installed, ec) ? installed.string() : std::string{};
}

QemuDevice::QemuDevice(const Options& options) : options_(options) {}

QemuDevice::~QemuDevice() { stop(); }

std::string QemuDevice::log() const {
  std::ifstream in(dir_ + "/semihosting.log");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::unique_ptr<Transport> QemuDevice::connect() {
  image_ = find_qemu_image();
  if (image_.empty()) {
    throw TransportError(
        "--device qemu: no firmware image (build it with `cmake --preset qemu-an386 && cmake --build "
        "--preset qemu-an386`, or set HMP_QEMU_ELF)");
  }
  if (!fs::exists(image_)) throw TransportError("--device qemu: " + image_ + " does not exist");

  char dir_template[] = "/tmp/hmp-qemu-XXXXXX";
  if (::mkdtemp(dir_template) == nullptr)
    throw TransportError(std::string("--device qemu: mkdtemp: ") + std::strerror(errno));
  dir_ = dir_template;
  std::vector<std::string> args = {qemu_emulator(),
                                   "-M",
                                   "mps2-an386",
                                   "-nographic",
                                   "-monitor",
                                   "none",
                                   "-semihosting-config",
                                   "enable=on,target=native",
                                   "-kernel",
                                   image_,
                                   "-append",
                                   "hz=" + std::to_string(options_.tick_hz) + (options_.net ? " link=net" : "")};
  return options_.net ? connect_net(args) : connect_uart(args);
}

// UART0 as a serial link: the emulator connects to a socket we listen on.
std::unique_ptr<Transport> QemuDevice::connect_uart(std::vector<std::string> args) {
  const std::string socket_path = dir_ + "/uart0.sock";
  listen_fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, socket_path.c_str(), sizeof addr.sun_path - 1);
  if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(listen_fd_, 1) != 0) {
    throw TransportError("--device qemu: cannot listen on " + socket_path + ": " + std::strerror(errno));
  }
  args.insert(args.end(), {"-chardev", "socket,id=uart0,path=" + socket_path, "-serial", "chardev:uart0"});
  start(args);
  pollfd p{listen_fd_, POLLIN, 0};
  if (::poll(&p, 1, 10'000) != 1) fail("--device qemu: the emulator did not connect to its UART within 10 s");
  const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) throw TransportError(std::string("--device qemu: accept: ") + std::strerror(errno));
  return SerialTransport::adopt(fd, "qemu");
}

// The Ethernet controller: QEMU's datagram back-end sends its frames to our socket and takes ours at its
// own, which exists once the emulator has set up its network.
std::unique_ptr<Transport> QemuDevice::connect_net(std::vector<std::string> args) {
  const std::string ours = dir_ + "/host.sock", theirs = dir_ + "/nic.sock";
  auto link = EtherTransport::bind(ours, "qemu:net");
  args.insert(args.end(),
              {"-serial", "null", "-netdev",
               "dgram,id=net0,local.type=unix,local.path=" + theirs + ",remote.type=unix,remote.path=" + ours, "-net",
               "nic,netdev=net0,model=lan9118"});
  start(args);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::error_code ec;
  while (!fs::exists(theirs, ec)) {
    if (std::chrono::steady_clock::now() >= deadline)
      fail("--device qemu:net: the emulator did not open its network within 10 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  link->connect(theirs);
  return link;
}

void QemuDevice::fail(const std::string& what) {
  const std::string why = log();  // the firmware's or the emulator's first words, if any
  stop();
  throw TransportError(what + (why.empty() ? std::string() : ": " + why.substr(0, why.find('\n'))));
}

void QemuDevice::start(const std::vector<std::string>& args) {
  std::string error;
  // Its own process group: the terminal's Ctrl-C is ours, and we stop the emulator.
  pid_ = start_child({args, "", "", "/dev/null", "/dev/null", dir_ + "/semihosting.log", true}, error);
  if (pid_ < 0) throw TransportError("--device qemu: cannot start " + args.front() + ": " + error);
}

void QemuDevice::stop() {
  if (pid_ > 0) {
    stop_child(pid_, std::chrono::seconds(2));  // the emulator this object started, by its id
    pid_ = -1;
  }
  if (listen_fd_ >= 0) ::close(listen_fd_);
  listen_fd_ = -1;
  if (!dir_.empty()) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    dir_.clear();
  }
}

}  // namespace hmp::transport
