#include "host/transport/serial_transport.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "host/common/error.hpp"
#include "host/transport/fd_wait.hpp"

namespace hmp::transport {

namespace {

using SteadyClock = std::chrono::steady_clock;

std::string os_error(int err) { return std::strerror(err); }

speed_t baud_constant(unsigned baud) {
  struct Entry {
    unsigned baud;
    speed_t constant;
  };
  static constexpr Entry kRates[] = {
      {9600, B9600},       {19200, B19200},     {38400, B38400},     {57600, B57600},
      {115200, B115200},   {230400, B230400},   {460800, B460800},   {500000, B500000},
      {576000, B576000},   {921600, B921600},   {1000000, B1000000}, {1152000, B1152000},
      {1500000, B1500000}, {2000000, B2000000}, {3000000, B3000000}, {4000000, B4000000},
  };
  for (const Entry& e : kRates) {
    if (e.baud == baud) return e.constant;
  }
  throw TransportError("unsupported serial speed " + std::to_string(baud) + " baud");
}

// Raw 8N1: no echo, no line editing, no CR/LF translation, no software flow control: every byte of a
// frame arrives as sent. Ptys accept the same settings (speed is meaningless there).
void make_raw(int fd, unsigned baud, const std::string& name) {
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0)
    throw TransportError("cannot read terminal settings of " + name + ": " + os_error(errno));
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | CSTOPB);
  tio.c_cc[VMIN] = 1;
  tio.c_cc[VTIME] = 0;
  if (baud != 0) {
    const speed_t speed = baud_constant(baud);
    ::cfsetispeed(&tio, speed);
    ::cfsetospeed(&tio, speed);
  }
  if (::tcsetattr(fd, TCSANOW, &tio) != 0)
    throw TransportError("cannot set " + name + " to raw mode: " + os_error(errno));
}

int connect_unix_socket(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) throw TransportError("socket path too long: " + path);
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw TransportError("cannot create a socket: " + os_error(errno));
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    const int err = errno;
    ::close(fd);
    throw TransportError("cannot connect to " + path + ": " + os_error(err));
  }
  return fd;
}

}  // namespace

std::unique_ptr<SerialTransport> SerialTransport::open(const std::string& path, const Options& options) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw TransportError("cannot open serial link " + path + ": " + os_error(errno));
  }
  if (S_ISSOCK(st.st_mode)) return adopt(connect_unix_socket(path), "serial:" + path, options);
  // A serial link is a character device (a tty) or a pipe; anything else would be a user's file that the
  // protocol's frames would be written into.
  if (!S_ISCHR(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    throw BadInput("serial link " + path + ": " + (S_ISDIR(st.st_mode) ? "a folder" : "not a serial port") +
                   " (a tty such as /dev/ttyACM0, a pipe or a socket)");
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    if (err == EACCES) {
      throw TransportError("permission denied on " + path + ": add yourself to its group (ls -l " + path +
                           "; usually dialout)");
    }
    throw TransportError("cannot open serial link " + path + ": " + os_error(err));
  }
  try {
    return adopt(fd, "serial:" + path, options);
  } catch (...) {
    ::close(fd);
    throw;
  }
}

std::unique_ptr<SerialTransport> SerialTransport::adopt(int fd, const std::string& name, const Options& options) {
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0) {
    throw TransportError("cannot use " + name + ": " + os_error(errno));
  }
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);
  if (::isatty(fd) != 0) make_raw(fd, options.baud, name);
  return std::unique_ptr<SerialTransport>(new SerialTransport(fd, name, options));
}

SerialTransport::SerialTransport(int fd, std::string name, const Options& options)
    : fd_(fd), name_(std::move(name)), options_(options) {
  struct stat st {};
  is_socket_ = ::fstat(fd_, &st) == 0 && S_ISSOCK(st.st_mode);
  wake_fd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_fd_ < 0) {
    ::close(fd_);
    throw TransportError("cannot create an eventfd: " + os_error(errno));
  }
}

SerialTransport::~SerialTransport() {
  close();
  ::close(fd_);
  ::close(wake_fd_);
}

void SerialTransport::close() {
  if (state_.mark_closed("closed by the host")) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof(one));
  }
}

framing::DecoderCounters SerialTransport::frame_counters() const {
  std::lock_guard lock(counters_mutex_);
  return frame_counters_;
}

bool SerialTransport::wait(short events, SteadyClock::time_point deadline) {
  return wait_fd(fd_, wake_fd_, events, deadline);
}

SerialTransport::ReadResult SerialTransport::read_available() {
  std::uint8_t buf[1024];
  for (;;) {
    const ssize_t n = ::read(fd_, buf, sizeof(buf));
    if (n > 0) {
      for (ssize_t i = 0; i < n; ++i) {
        if (decoder_.push(buf[i])) inbox_.push(decoder_.packet());
      }
      std::lock_guard lock(counters_mutex_);
      frame_counters_ = decoder_.counters();
      state_.set_dropped(frame_counters_.dropped());
      return ReadResult::data;
    }
    if (n == 0) {
      state_.mark_closed("peer closed " + name_);
      return ReadResult::closed;
    }
    const int err = errno;
    if (err == EINTR) continue;
    if (err == EAGAIN || err == EWOULDBLOCK) return ReadResult::would_block;
    // A pty whose other side closed reads EIO; a socket whose peer vanished, ECONNRESET.
    state_.mark_closed(err == EIO || err == ECONNRESET ? "peer closed " + name_ : name_ + ": " + os_error(err));
    return ReadResult::closed;
  }
}

Received SerialTransport::receive(Report& out, Timeout timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    if (inbox_.take(out, state_)) return Received::report;
    if (!state_.is_open()) return Received::closed;
    const ReadResult r = read_available();
    if (r != ReadResult::would_block) continue;
    if (SteadyClock::now() >= deadline) return Received::timeout;
    if (!wait(POLLIN, deadline) && SteadyClock::now() >= deadline) return Received::timeout;
  }
}

bool SerialTransport::write_all(const std::uint8_t* data, std::size_t size) {
  auto deadline = SteadyClock::now() + options_.write_timeout;
  while (size > 0) {
    if (!state_.is_open()) return false;
    const ssize_t n = is_socket_ ? ::send(fd_, data, size, MSG_NOSIGNAL) : ::write(fd_, data, size);
    if (n > 0) {
      data += n;
      size -= static_cast<std::size_t>(n);
      deadline = SteadyClock::now() + options_.write_timeout;  // progress: the peer is alive
      continue;
    }
    const int err = n < 0 ? errno : EAGAIN;
    if (err == EINTR) continue;
    if (err == EAGAIN || err == EWOULDBLOCK) {
      if (!wait(POLLOUT, deadline) && SteadyClock::now() >= deadline) {
        state_.mark_closed(
            name_ + " stalled: no byte taken for " +
            std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(options_.write_timeout).count()) +
            " ms");
        return false;
      }
      continue;
    }
    state_.mark_closed(err == EPIPE || err == EIO || err == ECONNRESET ? "peer closed " + name_
                                                                       : name_ + ": " + os_error(err));
    return false;
  }
  return true;
}

bool SerialTransport::send(const Report& report) {
  if (!state_.is_open()) return false;
  std::uint8_t frame[1 + framing::kMaxFrame];
  std::size_t size = 0;
  // A leading delimiter ends whatever a previous cut-off write (or the peer's reset) left in the
  // receiver's decoder, so that garbage costs no intact frame.
  if (resync_) frame[size++] = 0;
  size += framing::encode(report, protocol::wire_size(report), frame + size, sizeof(frame) - size);
  if (!write_all(frame, size)) {
    resync_ = true;
    return false;
  }
  resync_ = false;
  state_.count_sent();
  return true;
}

}  // namespace hmp::transport
