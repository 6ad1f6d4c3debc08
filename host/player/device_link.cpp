#include "host/player/device_link.hpp"

#include <fmt/format.h>

#include "host/transport/handshake.hpp"

namespace hmp::player {

std::int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

DeviceLink::DeviceLink(transport::Transport& link, const Options& options)
    : link_(&link), options_(options), clock_(ClockSync::Options{}) {}

DeviceLink::~DeviceLink() { stop_receiver(); }

protocol::HelloReply DeviceLink::greet() {
  std::uint16_t hello_seq;
  {
    std::lock_guard lock(mutex_);
    hello_seq = session_.take_seq();
  }
  const auto id = transport::say_hello(*link_, hello_seq, options_.hello_timeout);
  if (!id) {
    if (!link_->is_open())
      throw DeviceLost(fmt::format("device {}: link closed ({})", link_->name(), link_->closed_reason()));
    throw DeviceLost(fmt::format(
        "device {}: no answer to Hello within {} ms (sent every {} ms)", link_->name(), options_.hello_timeout.count(),
        std::chrono::duration_cast<std::chrono::milliseconds>(transport::kHelloResend).count()));
  }
  if (!id->compatible()) {
    throw LinkError(
        fmt::format("device {} speaks protocol version {}, this hmp speaks version {}: "
                    "update the firmware or hmp so that both match",
                    link_->name(), id->hello.protocol_version, protocol::kProtocolVersion));
  }
  std::lock_guard lock(mutex_);
  ClockSync::Options c;
  c.tick_hz = id->hello.tick_hz;
  clock_ = ClockSync(c);
  session_.restart(id->status);
  events_ = Events{};
  last_report_us_ = steady_us();
  dead_reason_.clear();
  return id->hello;
}

protocol::HelloReply DeviceLink::connect() {
  hello_ = greet();
  start_receiver();
  return hello_;
}

protocol::HelloReply DeviceLink::reconnect() { return attach(*link_); }

void DeviceLink::detach() { stop_receiver(); }

protocol::HelloReply DeviceLink::attach(transport::Transport& link) {
  stop_receiver();
  link_ = &link;
  hello_ = greet();
  start_receiver();
  return hello_;
}

void DeviceLink::start_receiver() {
  {
    std::lock_guard lock(mutex_);
    stop_ = false;
  }
  receiver_ = std::thread([this] { receive_loop(); });
}

void DeviceLink::stop_receiver() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  if (receiver_.joinable()) receiver_.join();
}

void DeviceLink::receive_loop() {
  protocol::Report report;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stop_) return;
    }
    const transport::Received got = link_->receive(report, options_.receive_poll);
    const std::int64_t now = steady_us();
    if (got == transport::Received::closed) {
      std::lock_guard lock(mutex_);
      dead_reason_ = link_->closed_reason().empty() ? "link closed" : link_->closed_reason();
      woken_ = true;
      wake_.notify_all();
      return;
    }
    if (got != transport::Received::report) continue;
    protocol::Message m;
    const bool ok = protocol::decode(report, m) == protocol::ErrorCode::none;
    std::lock_guard lock(mutex_);
    last_report_us_ = now;  // even an undecodable report shows the device is alive
    if (ok) on_report(m, now);
    woken_ = true;
    wake_.notify_all();
  }
}

// mutex_ held.
void DeviceLink::on_report(const protocol::Message& m, std::int64_t now) {
  switch (m.type) {
    case protocol::Type::sync_reply: {
      const SyncSample s{static_cast<std::int64_t>(m.sync_reply.host_time_us), now, m.sync_reply.tick,
                         m.sync_reply.subtick};
      if (s.sent_us > now) return;  // not one of ours
      if (clock_.add(s) == ClockSync::Verdict::reset) events_.restarted = true;
      return;
    }
    case protocol::Type::status:
      if (session_.status() && m.status.tick < session_.status()->tick) events_.restarted = true;
      session_.on_status(m.status);
      ++statuses_;
      return;
    case protocol::Type::started:
      for (std::uint8_t i = 0; i < m.started.count; ++i) events_.started.push_back(m.started.entries[i]);
      return;
    case protocol::Type::error:
      if (m.error.code == protocol::ErrorCode::queue_full) {
        events_.refused_full.push_back(m.error.seq);
      } else {
        events_.errors.push_back(m.error);
      }
      return;
    default: return;  // HelloReply outside a greeting, host types: nothing to do
  }
}

std::optional<std::uint16_t> DeviceLink::send(protocol::Message m) {
  protocol::Report report;
  std::uint16_t seq;
  {
    std::lock_guard lock(mutex_);
    seq = session_.number(m, report);  // counted in flight before sending: a quick Status must see it
  }
  if (!link_->send(report)) return std::nullopt;
  return seq;
}

std::optional<std::uint16_t> DeviceLink::send_sync() {
  protocol::Message m = protocol::make(protocol::Type::sync, 0);
  m.sync.host_time_us = static_cast<std::uint64_t>(steady_us());
  return send(m);
}

int DeviceLink::credit() const {
  std::lock_guard lock(mutex_);
  return session_.credit();
}

bool DeviceLink::processed(std::uint16_t seq) const {
  std::lock_guard lock(mutex_);
  return session_.processed(seq);
}

std::optional<protocol::Status> DeviceLink::status() const {
  std::lock_guard lock(mutex_);
  return session_.status();
}

std::uint64_t DeviceLink::statuses() const {
  std::lock_guard lock(mutex_);
  return statuses_;
}

DeviceLink::Events DeviceLink::take_events() {
  std::lock_guard lock(mutex_);
  Events out = std::move(events_);
  events_ = Events{};
  return out;
}

void DeviceLink::check() const {
  std::lock_guard lock(mutex_);
  if (!dead_reason_.empty()) throw DeviceLost(fmt::format("device {}: link lost ({})", link_->name(), dead_reason_));
  const std::int64_t silent = steady_us() - last_report_us_;
  if (silent > std::chrono::duration_cast<std::chrono::microseconds>(options_.silence_limit).count()) {
    throw DeviceLost(
        fmt::format("device {}: no report for {} ms: the device stopped answering", link_->name(), silent / 1000));
  }
}

std::optional<double> DeviceLink::position(std::int64_t host_us) const {
  std::lock_guard lock(mutex_);
  return clock_.position(host_us);
}

std::optional<std::uint64_t> DeviceLink::tick_at(std::int64_t host_us) const {
  std::lock_guard lock(mutex_);
  return clock_.tick_at(host_us);
}

std::size_t DeviceLink::sync_samples() const {
  std::lock_guard lock(mutex_);
  return clock_.samples();
}

double DeviceLink::max_sync_residual_ticks() const {
  std::lock_guard lock(mutex_);
  return clock_.max_residual_ticks();
}

double DeviceLink::best_transit_us() const {
  std::lock_guard lock(mutex_);
  return clock_.best_transit_us();
}

double DeviceLink::drift() const {
  std::lock_guard lock(mutex_);
  return clock_.drift();
}

void DeviceLink::wait(std::chrono::microseconds timeout) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, timeout, [this] { return woken_.exchange(false); });
}

// No lock: a MIDI callback in JACK's real-time thread calls this, and waiting there for a thread that
// holds mutex_ could cost the cycle. A wake that lands between wait()'s check and its sleep is seen at
// the wait's timeout.
void DeviceLink::notify() {
  woken_.store(true);
  wake_.notify_all();
}

}  // namespace hmp::player
