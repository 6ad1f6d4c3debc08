#pragma once
// Waiting on a link's descriptor and its wake-up eventfd (written by close()), for the transports that
// own a descriptor (serial, Ethernet frames).
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

namespace hmp::transport {

// Waits for `events` on `fd` or anything on `wake_fd`; false when the deadline passed first. Readiness,
// hang-up and errors all return true: the caller's next call says what happened.
inline bool wait_fd(int fd, int wake_fd, short events, std::chrono::steady_clock::time_point deadline) {
  for (;;) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    const int timeout_ms = left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1'000'000));
    pollfd fds[2] = {{fd, events, 0}, {wake_fd, POLLIN, 0}};
    const int n = ::poll(fds, 2, timeout_ms);
    if (n < 0 && errno == EINTR) continue;
    return n > 0;
  }
}

}  // namespace hmp::transport
