#pragma once
// The board-independent firmware core (design §7–§10). Owns the synthesis engine, the note schedule and
// the device state machine; talks to hardware only through the BoardSeam. No heap, no exceptions, no
// RTTI, no board header. docs/firmware.md describes the tick, the queues, the safety behaviour and the
// RAM budget.
//
// Threading, three contexts and no locks (docs/firmware.md, "Contexts"):
//  - on_packet() runs in the transport context: it decodes the report and puts it into a lock-free SPSC
//    inbox (producer);
//  - on_tick() in the tick timer interrupt: the inbox's consumer, and the only context that touches the
//    core's state;
//  - poll() in the background (the board's main loop, below the tick): encodes and sends the reports the
//    tick queued, and prepares the voices of the notes due next (NotePrep); two more SPSC rings.
// The tick never waits for the background: what the background has not done in time, the tick does
// itself (a voice) or counts (a report it had no room for). The inspection functions below are for a
// stopped tick (tests, the simulator).
#include <atomic>
#include <cstdint>

#include "firmware/board.hpp"
#include "firmware/drive.hpp"
#include "firmware/note_prep.hpp"
#include "firmware/note_queue.hpp"
#include "firmware/output_stage.hpp"
#include "firmware/spsc_queue.hpp"
#include "shared/common/version.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/synth/engine.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::fw {

// The build's tick rate (CMake's HMP_TICK_HZ), else the nominal one.
#ifdef HMP_TICK_HZ
inline constexpr std::uint32_t kDefaultTickHz = HMP_TICK_HZ;
#else
inline constexpr std::uint32_t kDefaultTickHz = synth::kNominalTickHz;
#endif
inline constexpr std::uint8_t kFirmwareMajor = version::kMajor, kFirmwareMinor = version::kMinor,
                              kFirmwarePatch = version::kPatch;

// Counters beyond the ones the Status report carries (all cumulative, wrapping).
struct Stats {
  std::uint32_t packets = 0;           // reports taken from the inbox
  std::uint32_t rejected = 0;          // reports refused, each answered by an Error (= Status.rejected)
  std::uint32_t queue_full = 0;        // of which note reports refused for lack of room (the host re-sends)
  std::uint32_t inbox_full = 0;        // reports on_packet could not take (the transport lost them)
  std::uint32_t late = 0;              // notes started after their scheduled tick
  std::uint32_t started = 0;           // notes started
  std::uint32_t engine_refused = 0;    // notes the engine would not start (counted in Status.rejected too)
  std::uint32_t tx_dropped = 0;        // device reports not sent (no room in the outbox or at the board)
  std::uint32_t prepare_requests = 0;  // notes handed to the background to prepare their voices
  std::uint32_t started_in_tick = 0;   // of `started`, notes whose voice the tick set up itself (not prepared in time)
  std::uint32_t drive_saturated = 0;   // drive ticks with a motor duty clamped to ±1
  std::uint32_t drive_not_converged = 0;  // drive ticks whose QP ran out of iterations (bounded answer)
  std::uint32_t drive_plan_late = 0;      // split drive: a plan was due but the last one was not done yet
};

// One received report, decoded in the transport context (the tick only acts on it), with its arrival time.
struct InboxEntry {
  protocol::Message message;                              // valid when error is none
  protocol::ErrorCode error = protocol::ErrorCode::none;  // what decode said
  std::uint8_t raw_type = 0;                              // the header as received, to refuse what did not decode
  std::uint16_t raw_seq = 0;
  bool estop = false;            // a well-formed emergency stop
  std::uint32_t rx_tick = 0;     // low 32 bits of the tick during which it arrived
  std::uint32_t rx_subtick = 0;  // board sub-tick counter at arrival (2^32 = one tick)
};

// Events that can repeat at packet rate are logged only when their count is a power of two: a hostile
// host cannot flood a slow log (semihosting), and the first occurrences are always visible.
constexpr bool worth_logging(std::uint32_t count) { return count != 0 && (count & (count - 1)) == 0; }

class Core {
 public:
  static constexpr std::uint32_t kInboxCapacity = 16;
  // Reports handled per tick: bounds the tick's time; USB full-speed HID delivers at most one per ms.
  static constexpr std::uint32_t kMaxPacketsPerTick = 4;
  // Notes started per tick: more than the voice count would only steal each other; the rest start on
  // the next tick (counted late).
  static constexpr std::uint32_t kMaxStartsPerTick = synth::kVoiceCount;
  static constexpr std::uint16_t kQueueCapacityReports = NoteQueue::kCapacity / protocol::kNotesPerBatch;
  // Notes are handed to the background for their voices this far ahead of their tick, one per tick.
  static constexpr std::uint32_t kPrepareAheadMs = 20;
  static constexpr std::uint32_t kOutboxCapacity = 16;  // device reports waiting for poll()

  // tick_hz: the rate on_tick() is called at (a build setting; tests run other rates). 0 → the default.
  // first_tick: where the tick counter starts (boards: 0; tests use it to cross the 2^32 wrap).
  explicit Core(const BoardSeam& board, std::uint32_t tick_hz = kDefaultTickHz, std::uint64_t first_tick = 0,
                const DriveParams& drive = {});
  Core(const Core&) = delete;
  Core& operator=(const Core&) = delete;

  // ---- transport context ----
  // Decodes one report and queues it for the next tick. false: the inbox is full and the report was not
  // taken (a board that can hold it back, e.g. by NAKing a USB transfer, checks inbox_has_room() first).
  // A well-formed emergency stop acts on the next tick even then.
  bool on_packet(const protocol::Report& report) { return on_decoded(decode_packet(report)); }
  // The same in two steps, for a board that must keep a tick from falling between the core's arrival
  // stamp and its own record of it: decode_packet (the long part: any context, touches no core state),
  // then on_decoded with interrupts masked (a copy and the stamp). `stamped_tick` receives the tick
  // stamped on the report.
  static InboxEntry decode_packet(const protocol::Report& report);
  bool on_decoded(const InboxEntry& decoded, std::uint32_t* stamped_tick = nullptr);
  bool inbox_has_room() const { return inbox_.has_room(); }
  std::uint32_t inbox_free() const { return kInboxCapacity - inbox_.size(); }  // at least this many
  // The link to the host is gone for now (USB suspend): on the next tick, as the host watchdog would but
  // at once, a playing device fades out (within the fade time, ≤ 20 ms) and pauses, its notes flushed.
  // Not a fault: the host may come back and play again.
  void on_link_lost() { link_lost_.store(true, std::memory_order_release); }
  // The board's emergency-stop input tripped (any context): acts on the next tick as an Estop report does.
  void on_estop_input() { estop_pending_.store(true, std::memory_order_release); }

  // ---- tick context ----
  void on_tick();

  // ---- background context (below the tick: the board's main loop; the simulator after each tick) ----
  // Sends the reports the tick queued, then prepares the voices of the notes due next. Returns whether
  // there was anything to do. Call it whenever the tick may have queued work; it never blocks.
  bool poll() {
    const bool planned = plan_drive();  // first: the coming ticks render from it
    const bool sent = send_reports();
    return prepare_voices() || sent || planned;
  }
  bool send_reports();    // the first part of poll(): false if there were none
  bool prepare_voices();  // the second: false if there was nothing to prepare
  bool plan_drive();      // the split drive's slow part, when the tick asked for it (false: it did not)

  // ---- inspection (tick stopped) ----
  std::uint32_t tick_hz() const { return tick_hz_; }
  std::uint64_t tick() const { return tick_; }
  protocol::State state() const { return state_; }
  std::uint32_t faults() const { return faults_; }
  Stats stats() const;  // a copy: tx_dropped adds the reports the background could not send
  const synth::Engine& engine() const { return engine_; }
  const protocol::Settings& settings() const { return settings_; }
  float last_output() const { return last_output_; }
  std::uint16_t queued_notes() const { return static_cast<std::uint16_t>(queue_.size() + prep_.pending()); }
  std::uint8_t prepared_pending() const { return prep_.pending(); }  // queued notes handed to the background
  protocol::Status status() const;                                   // what a Status report sent now would carry
  void write_status(protocol::Status& s) const;                      // the same, into a report being built
  bool has_drive() const { return has_drive_; }
  const Drive& drive() const { return drive_; }
  const float (&duties() const)[kMotorCount] { return duty_; }  // the last ones sent to the board
  std::uint16_t reports_sent() const { return tx_seq_; }        // device reports made so far (wrapping)

 private:
  // core.cpp: the tick
  void start_due_notes();
  void request_upcoming();
  void flush_notes();
  std::uint16_t free_note_slots() const { return static_cast<std::uint16_t>(queue_.free_slots() - prep_.pending()); }
  void check_watchdog();
  void send_periodic_reports();
  void run_drive();
  void run_split_drive(bool safe);
  void apply_drive_tick(const DriveTick& t);
  void drive_fault(std::uint32_t faults);
  std::uint64_t rx_tick64(std::uint32_t rx_tick) const;
  // core_commands.cpp: one handler per host report type
  void handle(const InboxEntry& entry);
  void on_hello(const protocol::Message& m);
  void on_sync(const protocol::Message& m, const InboxEntry& entry);
  protocol::ErrorCode check_playable(std::uint8_t preset, std::uint32_t freq_q20) const;
  void on_notes(const protocol::Message& m, std::uint64_t rx_tick);
  void on_long_note(const protocol::Message& m);
  void on_live(const protocol::Message& m);
  void on_preset(const protocol::Message& m);
  void on_settings(const protocol::Message& m);
  void on_transport(const protocol::Message& m);
  void emergency_stop();
  void fade_out(protocol::State next);
  void apply_settings();
  // core_reports.cpp: device → host reports
  void send(protocol::Message& m);
  // The outbox slot for a report of this type, with its seq, for the caller to fill in place and then
  // commit with outbox_.commit(); nullptr (counted) when the outbox is full.
  protocol::Message* begin_report(protocol::Type type);
  void reject(protocol::ErrorCode code, std::uint16_t seq, std::uint8_t type);
  void note_started(const QueuedNote& q);
  void flush_started();
  void log_event(const char* what, std::uint64_t value);

  BoardSeam board_;
  std::uint32_t tick_hz_;
  synth::SynthConfig synth_cfg_;
  synth::Engine engine_;
  NoteQueue queue_;
  NotePrep prep_;
  std::uint32_t prepare_ahead_ticks_ = 1;
  OutputStage output_;
  SpscQueue<InboxEntry, kInboxCapacity> inbox_;
  SpscQueue<protocol::Message, kOutboxCapacity> outbox_;
  std::uint32_t outbox_full_ = 0;              // reports the tick had no room for
  std::atomic<std::uint32_t> send_failed_{0};  // written by the background only
  Drive drive_;
  // The split drive's hand-over (drive.hpp): the tick asks for a plan every ticks_per_plan() ticks with
  // the encoder counts; the background computes it into the buffer the tick is not reading and flips
  // plan_front_. A tick never holds a plan across ticks, and the background never interrupts the tick.
  PlanInput plan_in_{};
  std::atomic<bool> plan_wanted_{false};
  DrivePlan plans_[2]{};
  std::atomic<std::uint8_t> plan_front_{0};
  std::atomic<std::uint32_t> plan_seq_{0};  // plans made (written by the background)
  std::uint32_t plan_seen_ = 0;             // the last plan whose faults the tick took
  std::uint32_t plan_countdown_ = 0;
  float duty_[kMotorCount]{};
  float force_n_ = 0.0f;  // the drive's achieved force along the direction (N)
  GripReading grip_{};    // where the drive's pose puts the grip (Status)
  bool has_drive_ = false;
  protocol::Settings settings_{};
  protocol::Started started_{};
  Stats stats_{};

  std::uint64_t tick_ = 0;                 // the tick being (or last) processed
  std::atomic<std::uint32_t> tick_lo_{0};  // its low 32 bits, for the transport context
  std::atomic<bool> estop_pending_{false};
  std::atomic<bool> link_lost_{false};
  std::atomic<std::uint32_t> inbox_lost_{0};  // written by the transport context only
  std::uint64_t last_host_tick_ = 0;          // arrival of the last well-formed host report (watchdog)
  std::uint64_t song_tick_ = 0;               // last seek target (informational, logged)
  std::uint32_t watchdog_ticks_ = 0;
  std::uint32_t status_period_playing_ = 1, status_period_idle_ = 1;
  std::uint32_t status_countdown_ = 1;  // ticks until the next Status (the next one included)
  std::uint32_t faults_ = protocol::fault_none;
  protocol::State state_ = protocol::State::idle;
  std::uint16_t last_seq_ = 0;   // last well-formed host report processed (done or refused)
  bool version_locked_ = false;  // a Hello of another version came last
  std::uint16_t tx_seq_ = 0;
  float last_output_ = 0.0f;
};

}  // namespace hmp::fw
