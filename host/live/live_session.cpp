#include "host/live/live_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hmp::live {
namespace {

constexpr std::int64_t kSyncPeriodUs = 100'000, kShowPeriodUs = 200'000, kPortCheckUs = 500'000;
// The output's ramp-in after play: short, as the first key may come at once (a song's player has 500 ms).
constexpr std::uint16_t kRampInMs = 20;
constexpr std::size_t kInFlight = 8;       // Live reports sent and not yet processed by the device
constexpr std::size_t kPlayedKept = 4096;  // notes the window can show: minutes of fast playing

// sent_on_'s key: a note-on by its report's seq and its index in the report.
std::uint32_t sent_key(std::uint16_t seq, std::uint32_t index) { return static_cast<std::uint32_t>(seq) << 8 | index; }

}  // namespace

LiveSession::LiveSession(player::DeviceLink& link, const MapperOptions& options, bool keep_notes)
    : link_(link), mapper_(options), keep_notes_(keep_notes) {}

// The mapper's events for one message (from `first_event` on) as notes of the window: a note-on starts
// one, a release ends the channel's sounding note of that key.
void LiveSession::record_played(const ChannelMessage& m, std::size_t first_event) {
  const std::int64_t now = session_us();
  const std::lock_guard<std::mutex> lock(played_mutex_);
  for (std::size_t i = first_event; i < events_.size(); ++i) {
    const DeviceEvent& e = events_[i];
    if (e.event.op == protocol::LiveOp::on) {
      played_.push_back({e.track, e.event.key, m.data2, now, INT64_MAX});
      if (played_.size() > kPlayedKept) played_.pop_front();
    } else if (e.event.op == protocol::LiveOp::off) {
      for (auto it = played_.rbegin(); it != played_.rend(); ++it) {
        if (it->channel != e.track || it->key != e.event.key || it->end_us != INT64_MAX) continue;
        it->end_us = now;
        break;
      }
    }
  }
}

void LiveSession::played(std::int64_t t0_us, std::int64_t t1_us, std::vector<PlayedNote>& out) const {
  const std::int64_t now = session_us();
  const std::lock_guard<std::mutex> lock(played_mutex_);
  for (const PlayedNote& n : played_) {
    if (n.start_us >= t1_us || n.end_us <= t0_us) continue;
    PlayedNote shown = n;
    shown.end_us = std::min(n.end_us, std::max(now, n.start_us + 1));
    out.push_back(shown);
  }
}

void LiveSession::receive(void* self, const std::uint8_t* bytes, std::size_t size) {
  auto* me = static_cast<LiveSession*>(self);
  if (me->ring_.push(player::steady_us(), bytes, size)) me->link_.notify();
}

// The events waiting, in order, in reports of up to five events of one track: a chord or a burst fills
// reports instead of sending one per message. At most kInFlight reports the device has not processed yet
// (Status.last_seq): its inbox holds 16 and it takes 4 a tick, and a serial link cannot hold a report
// back as USB does, so a burst beyond that waits here (counted in held) instead of being lost there.
void LiveSession::send_events() {
  while (!in_flight_.empty() && link_.processed(in_flight_.front())) in_flight_.pop_front();
  // The events due: those of messages that came at least the delay ago (they are in arrival order).
  const std::int64_t due_before = player::steady_us() - delay_us_;
  const std::size_t due =
      static_cast<std::size_t>(std::upper_bound(event_us_.begin(), event_us_.end(), due_before) - event_us_.begin());
  std::size_t i = 0;
  while (i < due && in_flight_.size() < kInFlight) {
    protocol::Message m = protocol::make(protocol::Type::live, 0);
    m.live.track = events_[i].track;
    const std::size_t first = i;
    while (i < due && events_[i].track == m.live.track && m.live.count < protocol::kNotesPerBatch)
      m.live.events[m.live.count++] = events_[i++].event;
    const std::optional<std::uint16_t> seq = link_.send(m);
    if (!seq) return;  // the link is dead: check() says so
    in_flight_.push_back(*seq);
    const std::int64_t sent_us = player::steady_us();
    for (std::uint8_t k = 0; k < m.live.count; ++k) {
      if (m.live.events[k].op != protocol::LiveOp::on) continue;
      std::size_t record = SIZE_MAX;
      if (keep_notes_) {
        record = notes_.size();
        notes_.push_back({m.live.track, m.live.events[k].key, event_us_[first + k], sent_us, 0, 0});
      }
      sent_on_.insert_or_assign(sent_key(*seq, k), SentOn{event_us_[first + k], record});
    }
  }
  events_.erase(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(i));
  event_us_.erase(event_us_.begin(), event_us_.begin() + static_cast<std::ptrdiff_t>(i));
  progress_.held = due - i;
  progress_.most_held = std::max(progress_.most_held, progress_.held);
}

void LiveSession::take_device_events() {
  player::DeviceLink::Events ev = link_.take_events();
  const std::int64_t now = player::steady_us();
  for (const protocol::StartedEntry& s : ev.started) {
    ++progress_.started;
    const auto it = sent_on_.find(sent_key(s.seq, s.index));
    if (it == sent_on_.end()) continue;
    const SentOn& o = it->second;
    progress_.latency_ms.push_back(static_cast<double>(now - o.received_us) / 1000.0);
    if (o.record != SIZE_MAX) {
      notes_[o.record].started_us = now;
      notes_[o.record].actual_tick = s.actual_tick;
    }
    sent_on_.erase(it);
  }
  for (const protocol::Error& e : ev.errors) {
    ++progress_.refused;
    if (e.type == static_cast<std::uint8_t>(protocol::Type::live))
      for (std::uint32_t k = 0; k < protocol::kNotesPerBatch; ++k) sent_on_.erase(sent_key(e.seq, k));
    progress_.last_error = std::string(protocol::name(e.code)) + " (report " + std::to_string(e.seq) + ", " +
                           protocol::name(static_cast<protocol::Type>(e.type)) + ")";
  }
}

LiveEnd LiveSession::run(const MidiInput& input, double seconds, const std::function<bool()>& stop,
                         const std::function<void(const LiveProgress&)>& show) {
  protocol::Message m = protocol::make(protocol::Type::settings, 0);
  m.settings.ramp_in_ms = kRampInMs;
  link_.send(m);
  m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = protocol::TransportOp::play;
  link_.send(m);
  const std::int64_t start = player::steady_us();
  std::int64_t next_sync = start, next_show = start, next_port_check = start + kPortCheckUs;
  for (;;) {
    const std::int64_t now = player::steady_us();
    if (stop()) return LiveEnd::stopped;
    if (seconds > 0 && static_cast<double>(now - start) >= seconds * 1e6) return LiveEnd::time_up;
    ring_.drain([&](const MidiChunk& c) {
      stream_.feed(c.bytes, c.size, [&](const ChannelMessage& msg) {
        const std::size_t first = events_.size();
        mapper_.on_message(msg, events_);
        record_played(msg, first);
        if (hear_) heard_.push_back(msg);
      });
      event_us_.resize(events_.size(), c.received_us);
    });
    progress_.dropped = ring_.dropped();
    send_events();
    // The sound after the device's share: it may wait for the audio thread's lock.
    for (const ChannelMessage& msg : heard_) hear_(msg);
    heard_.clear();
    link_.check();
    take_device_events();
    if (now >= next_sync) {
      link_.send_sync();
      next_sync = now + kSyncPeriodUs;
    }
    if (now >= next_port_check) {
      if (!input.present()) return LiveEnd::port_gone;
      next_port_check = now + kPortCheckUs;
    }
    if (now >= next_show) {
      progress_.counts = mapper_.counts();
      show(progress_);
      next_show = now + kShowPeriodUs;
    }
    // Until the link has news, the next delayed event is due, or 10 ms (the Sync, the port check).
    std::int64_t wait_us = 10'000;
    if (!events_.empty()) {
      const std::int64_t until_due = event_us_.front() + delay_us_ - player::steady_us();
      if (until_due > 0) wait_us = std::min(wait_us, until_due);
    }
    link_.wait(std::chrono::microseconds(wait_us));
  }
}

void LiveSession::finish() {
  protocol::Message m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = protocol::TransportOp::stop;
  link_.send(m);
  const std::int64_t until = player::steady_us() + 100'000;  // the last Started reports
  while (player::steady_us() < until) {
    link_.wait(std::chrono::microseconds(10'000));
    take_device_events();
  }
  progress_.counts = mapper_.counts();
  progress_.dropped = ring_.dropped();
}

}  // namespace hmp::live
