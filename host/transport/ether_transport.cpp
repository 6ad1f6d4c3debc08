#include "host/transport/ether_transport.hpp"

#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "host/transport/fd_wait.hpp"
#include "shared/framing/ether_frame.hpp"

namespace hmp::transport {

namespace {

using SteadyClock = std::chrono::steady_clock;
constexpr auto kSendTimeout = std::chrono::seconds(2);  // a peer that takes no frame for this long is gone

sockaddr_un unix_address(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) throw TransportError("socket path too long: " + path);
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  return addr;
}

}  // namespace

std::unique_ptr<EtherTransport> EtherTransport::bind(const std::string& path, const std::string& name) {
  const sockaddr_un addr = unix_address(path);
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) throw TransportError(std::string("cannot create a socket: ") + std::strerror(errno));
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    throw TransportError("cannot bind " + path + ": " + std::strerror(err));
  }
  const int wake_fd = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_fd < 0) {
    ::close(fd);
    throw TransportError(std::string("cannot create an eventfd: ") + std::strerror(errno));
  }
  return std::unique_ptr<EtherTransport>(new EtherTransport(fd, wake_fd, name));
}

EtherTransport::EtherTransport(int fd, int wake_fd, std::string name)
    : fd_(fd), wake_fd_(wake_fd), name_(std::move(name)) {}

EtherTransport::~EtherTransport() {
  close();
  ::close(fd_);
  ::close(wake_fd_);
}

void EtherTransport::connect(const std::string& path) {
  const sockaddr_un addr = unix_address(path);
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    throw TransportError("cannot connect to " + path + ": " + std::strerror(errno));
}

void EtherTransport::close() {
  if (state_.mark_closed("closed by the host")) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof(one));
  }
}

bool EtherTransport::wait(short events, SteadyClock::time_point deadline) const {
  return wait_fd(fd_, wake_fd_, events, deadline);
}

Received EtherTransport::receive(Report& out, Timeout timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    if (inbox_.take(out, state_)) return Received::report;
    if (!state_.is_open()) return Received::closed;
    std::uint8_t frame[2048];
    const ssize_t n = ::recv(fd_, frame, sizeof frame, 0);
    if (n >= 0) {
      const std::uint8_t* report = framing::ether::payload_of(frame, static_cast<std::size_t>(n));
      if (report == nullptr) {
        state_.count_dropped();
        continue;
      }
      inbox_.push(report);
      continue;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      state_.mark_closed(name_ + ": " + std::strerror(errno));
      continue;
    }
    if (SteadyClock::now() >= deadline) return Received::timeout;
    if (!wait(POLLIN, deadline) && SteadyClock::now() >= deadline) return Received::timeout;
  }
}

bool EtherTransport::send(const Report& report) {
  std::uint8_t frame[framing::ether::kFrameBytes];
  framing::ether::build(report, framing::ether::kHostMac, framing::ether::kDeviceMac, frame);
  const auto deadline = SteadyClock::now() + kSendTimeout;
  for (;;) {
    if (!state_.is_open()) return false;
    if (::send(fd_, frame, sizeof frame, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof frame)) {
      state_.count_sent();
      return true;
    }
    const int err = errno;
    if (err == EINTR) continue;
    if (err == EAGAIN || err == EWOULDBLOCK) {
      if (!wait(POLLOUT, deadline) && SteadyClock::now() >= deadline) {
        state_.mark_closed(name_ + " stalled: no frame taken for " + std::to_string(kSendTimeout.count()) + " s");
        return false;
      }
      continue;
    }
    // No one at the peer's address any more: the emulator has exited.
    state_.mark_closed(err == ECONNREFUSED || err == ENOENT ? "peer closed " + name_
                                                            : name_ + ": " + std::strerror(err));
    return false;
  }
}

}  // namespace hmp::transport
