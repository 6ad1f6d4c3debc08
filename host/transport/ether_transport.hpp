#pragma once
// Reports as Ethernet frames over a unix-domain datagram socket (design §9, §14;
// shared/framing/ether_frame.hpp): the link of `--device qemu:net`, where QEMU's network back-end
// (`-netdev dgram` with unix sockets) hands each frame the emulated Ethernet controller sends to this
// socket, and each datagram sent here to the controller. One report per datagram, whole: no byte
// stream to resynchronise; a datagram that is not one of our frames is dropped and counted.
//
// A datagram socket has no hang-up: a peer that exits is noticed when a send finds no one there (the
// player sends at least a Sync every 100 ms).
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "host/transport/link_state.hpp"
#include "host/transport/report_inbox.hpp"
#include "host/transport/transport.hpp"

namespace hmp::transport {

class EtherTransport final : public TransportWithState {
 public:
  // Binds a socket at `path` (to which the peer sends). Throws TransportError with a one-line message.
  static std::unique_ptr<EtherTransport> bind(const std::string& path, const std::string& name);
  ~EtherTransport() override;
  // Sends to the peer's socket at `path` from now on. Throws TransportError.
  void connect(const std::string& path);

  bool send(const Report& report) override;
  Received receive(Report& out, Timeout timeout) override;
  std::string name() const override { return name_; }
  void close() override;

 private:
  EtherTransport(int fd, int wake_fd, std::string name);
  bool wait(short events, std::chrono::steady_clock::time_point deadline) const;

  int fd_ = -1;
  int wake_fd_ = -1;  // eventfd written by close(): wakes a receive()/send() blocked in poll
  std::string name_;
  ReportInbox inbox_;  // receive thread only
};

}  // namespace hmp::transport
