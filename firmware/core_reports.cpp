// Device → host reports and the log.
#include "firmware/core.hpp"
#include "firmware/log_line.hpp"

namespace hmp::fw {

// Into the outbox: poll() encodes and sends it (encoding is a few hundred instructions the tick need not
// spend). A full outbox drops the report, counted with the ones the board could not take.
void Core::send(protocol::Message& m) {
  protocol::Message* slot = begin_report(m.type);
  m.seq = tx_seq_;
  if (slot == nullptr) return;
  *slot = m;
  outbox_.commit();
}

protocol::Message* Core::begin_report(protocol::Type type) {
  tx_seq_ = protocol::next_seq(tx_seq_);
  protocol::Message* slot = outbox_.prepare();
  if (slot == nullptr) {
    ++outbox_full_;
    return nullptr;
  }
  slot->type = type;
  slot->seq = tx_seq_;
  return slot;
}

// Counts the refusal and answers it. A note report refused for lack of room also latches
// fault_queue_overflow: a host that follows the credit rule (docs/protocol.md) never causes one.
void Core::reject(protocol::ErrorCode code, std::uint16_t seq, std::uint8_t type) {
  ++stats_.rejected;
  if (code == protocol::ErrorCode::queue_full) {
    ++stats_.queue_full;
    faults_ |= protocol::fault_queue_overflow;
  }
  if (worth_logging(stats_.rejected)) {
    LogLine line;
    // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
    // clang-format off
    line.text("refused report: ").text(protocol::name(code)).text(", type ").num(type).text(", seq ").num(seq)
        .text(", refusals ").num(stats_.rejected);
    // clang-format on
    if (board_.log != nullptr) board_.log(board_.ctx, line.c_str());
  }
  protocol::Message m = protocol::make(protocol::Type::error, 0);
  m.error.code = code;
  m.error.seq = seq;
  m.error.type = type;
  send(m);
}

void Core::note_started(const QueuedNote& q) {
  protocol::StartedEntry& e = started_.entries[started_.count++];
  e.seq = q.seq;
  e.index = q.index;
  e.scheduled_tick = static_cast<std::uint32_t>(q.note.start_tick);
  e.actual_tick = static_cast<std::uint32_t>(tick_);
  if (started_.count == protocol::kNotesPerBatch) flush_started();
}

void Core::flush_started() {
  if (started_.count == 0) return;
  // Built in place (the Status tick sends it): entries past count are not encoded, so only count resets.
  if (protocol::Message* m = begin_report(protocol::Type::started)) {
    m->started = started_;
    outbox_.commit();
  }
  started_.count = 0;
}

void Core::log_event(const char* what, std::uint64_t value) {
  if (board_.log == nullptr) return;
  LogLine line;
  line.text(what).num(value);
  board_.log(board_.ctx, line.c_str());
}

}  // namespace hmp::fw
