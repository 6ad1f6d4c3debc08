#pragma once
// The player's side of one device session (docs/protocol.md): a receiver thread that decodes what the
// device says, the session rules (numbering, flow-control credit: transport::HostSession) shared with the
// receiver under one lock, and the clock sync fed by SyncReplies.
//
// Threads: one thread sends (the player); the receiver thread owned here reads the transport. Every
// query is safe from the player thread while the receiver runs.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "host/player/clock_sync.hpp"
#include "host/transport/host_session.hpp"
#include "host/transport/transport.hpp"

namespace hmp::player {

// The session cannot go on: the link died, the device stopped answering, or it speaks another protocol
// version. One line, for the user.
class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The device is gone (its link closed, or it stopped answering): it may come back (a cable put back, a
// board that rebooted), unlike a device that speaks another protocol version.
class DeviceLost : public LinkError {
 public:
  using LinkError::LinkError;
};

std::int64_t steady_us();  // host clock for the Sync exchange: µs of std::chrono::steady_clock

class DeviceLink {
 public:
  struct Options {
    std::chrono::milliseconds hello_timeout{1000};
    // The device sends a Status at least every 100 ms: this long without any report means it is gone.
    std::chrono::milliseconds silence_limit{500};
    std::chrono::microseconds receive_poll{20'000};
  };

  // What the receiver collected since the last take_events().
  struct Events {
    std::vector<protocol::StartedEntry> started;
    std::vector<std::uint16_t> refused_full;  // note reports refused with queue_full: send them again
    std::vector<protocol::Error> errors;      // every other Error the device sent
    bool restarted = false;                   // the device's clock went back: it rebooted
  };

  DeviceLink(transport::Transport& link, const Options& options);
  explicit DeviceLink(transport::Transport& link) : DeviceLink(link, Options{}) {}
  ~DeviceLink();
  DeviceLink(const DeviceLink&) = delete;
  DeviceLink& operator=(const DeviceLink&) = delete;

  // Greets the device (Hello → HelloReply → Status) and starts the receiver. Throws LinkError: no
  // answer, link closed, or a device of another protocol version.
  protocol::HelloReply connect();
  // After a restart: stops the receiver, greets again, forgets the old clock and credit.
  protocol::HelloReply reconnect();
  // A lost device: detach() stops the receiver, so that the old transport may be destroyed; attach()
  // greets the device behind `link` (the same one, opened again) as connect() does. attach() throws
  // DeviceLost while it does not answer yet (still booting).
  void detach();
  protocol::HelloReply attach(transport::Transport& link);

  // Numbers and sends a report; nullopt when the link is dead (check()).
  std::optional<std::uint16_t> send(protocol::Message m);
  std::optional<std::uint16_t> send_sync();
  // Note reports the device will still accept: queue_free − note reports sent after its last_seq.
  int credit() const;
  // The device has processed the report numbered `seq` (Status.last_seq reached it).
  bool processed(std::uint16_t seq) const;

  std::optional<protocol::Status> status() const;
  std::uint64_t statuses() const;  // Status reports received so far
  Events take_events();
  // Throws DeviceLost when the link is closed or silent for too long.
  void check() const;

  // The clock (nullopt until the first SyncReply).
  std::optional<double> position(std::int64_t host_us) const;
  std::optional<std::uint64_t> tick_at(std::int64_t host_us) const;
  std::size_t sync_samples() const;
  double max_sync_residual_ticks() const;
  double best_transit_us() const;
  double drift() const;

  // Sleeps until a report arrives, notify() is called, or `timeout` passes.
  void wait(std::chrono::microseconds timeout);
  void notify();

  const protocol::HelloReply& hello() const { return hello_; }
  transport::Transport& transport() { return *link_; }

 private:
  void start_receiver();
  void stop_receiver();
  void receive_loop();
  void on_report(const protocol::Message& m, std::int64_t now);
  protocol::HelloReply greet();

  transport::Transport* link_;
  Options options_;
  protocol::HelloReply hello_{};

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> woken_{false};
  ClockSync clock_;
  transport::HostSession session_;
  std::uint64_t statuses_ = 0;
  Events events_;
  std::int64_t last_report_us_ = 0;
  std::string dead_reason_;
  bool stop_ = false;
  std::thread receiver_;
};

}  // namespace hmp::player
