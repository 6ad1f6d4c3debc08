#pragma once
// The board-independent firmware core (SPEC §7–§10). Owns the synthesis engine, the note schedule and
// the device state machine; talks to hardware only through the BoardSeam. No heap, no exceptions, no
// RTTI, no board header. docs/firmware.md describes the tick, the queues, the safety behaviour and the
// RAM budget.
//
// Threading: on_packet() runs in the transport context (producer of a lock-free SPSC inbox), on_tick()
// in the tick timer interrupt (consumer). Everything else in the core is touched only from on_tick(),
// so there are no locks. The inspection functions below are for a stopped tick (tests, the simulator).
#include <atomic>
#include <cstdint>

#include "firmware/board.hpp"
#include "firmware/drive.hpp"
#include "firmware/note_queue.hpp"
#include "firmware/output_stage.hpp"
#include "firmware/spsc_queue.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/synth/engine.hpp"

#ifndef HMP_TICK_HZ
#define HMP_TICK_HZ 1000
#endif

namespace hmp::fw {

inline constexpr std::uint32_t kDefaultTickHz = HMP_TICK_HZ;
inline constexpr std::uint8_t kFirmwareMajor = 0, kFirmwareMinor = 1, kFirmwarePatch = 0;

// Counters beyond the ones the Status report carries (all cumulative, wrapping).
struct Stats {
  std::uint32_t packets = 0;       // reports taken from the inbox
  std::uint32_t rejected = 0;      // reports refused, each answered by an Error (= Status.rejected)
  std::uint32_t queue_full = 0;    // of which note reports refused for lack of room (the host re-sends)
  std::uint32_t inbox_full = 0;    // reports on_packet could not take (the transport lost them)
  std::uint32_t late = 0;          // notes started after their scheduled tick
  std::uint32_t started = 0;       // notes started
  std::uint32_t engine_refused = 0;  // notes the engine would not start (counted in Status.rejected too)
  std::uint32_t tx_dropped = 0;    // device reports not sent (the board had no room)
  std::uint32_t drive_saturated = 0;      // drive ticks with a motor duty clamped to ±1
  std::uint32_t drive_not_converged = 0;  // drive ticks whose QP ran out of iterations (bounded answer)
};

// One received report with its arrival time.
struct InboxEntry {
  protocol::Report bytes;
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

  // tick_hz: the rate on_tick() is called at (a build setting; tests run other rates). 0 → the default.
  // first_tick: where the tick counter starts (boards: 0; tests use it to cross the 2^32 wrap).
  explicit Core(const BoardSeam& board, std::uint32_t tick_hz = kDefaultTickHz, std::uint64_t first_tick = 0,
                const DriveParams& drive = {});
  Core(const Core&) = delete;
  Core& operator=(const Core&) = delete;

  // ---- transport context ----
  // Queues one report for the next tick. false: the inbox is full and the report was not taken (a board
  // that can hold it back, e.g. by NAKing a USB transfer, checks inbox_has_room() first). A well-formed
  // emergency stop acts on the next tick even then.
  bool on_packet(const protocol::Report& report);
  bool inbox_has_room() const { return inbox_.has_room(); }

  // ---- tick context ----
  void on_tick();

  // ---- inspection (tick stopped) ----
  std::uint32_t tick_hz() const { return tick_hz_; }
  std::uint64_t tick() const { return tick_; }
  protocol::State state() const { return state_; }
  std::uint32_t faults() const { return faults_; }
  const Stats& stats() const { return stats_; }
  const synth::Engine& engine() const { return engine_; }
  const protocol::Settings& settings() const { return settings_; }
  float last_output() const { return last_output_; }
  std::uint16_t queued_notes() const { return queue_.size(); }
  protocol::Status status() const;  // what a Status report sent now would carry
  bool has_drive() const { return has_drive_; }
  const Drive& drive() const { return drive_; }
  const float (&duties() const)[kMotorCount] { return duty_; }  // the last ones sent to the board
  std::uint16_t reports_sent() const { return tx_seq_; }  // device reports made so far (wrapping)

 private:
  // core.cpp: the tick
  void start_due_notes();
  void check_watchdog();
  void send_periodic_reports();
  void run_drive();
  void drive_fault(std::uint32_t faults);
  std::uint64_t rx_tick64(std::uint32_t rx_tick) const;
  // core_commands.cpp: one handler per host report type
  void handle(const InboxEntry& entry);
  void on_hello(const protocol::Message& m);
  void on_sync(const protocol::Message& m, const InboxEntry& entry);
  protocol::ErrorCode check_playable(std::uint8_t preset, std::uint32_t freq_q20) const;
  void on_notes(const protocol::Message& m, std::uint64_t rx_tick);
  void on_long_note(const protocol::Message& m);
  void on_preset(const protocol::Message& m);
  void on_settings(const protocol::Message& m);
  void on_transport(const protocol::Message& m);
  void emergency_stop();
  void fade_out(protocol::State next);
  void apply_settings();
  // core_reports.cpp: device → host reports
  void send(protocol::Message& m);
  void reject(protocol::ErrorCode code, std::uint16_t seq, std::uint8_t type);
  void note_started(const QueuedNote& q);
  void flush_started();
  void log_event(const char* what, std::uint64_t value);

  BoardSeam board_;
  std::uint32_t tick_hz_;
  synth::SynthConfig synth_cfg_;
  synth::Engine engine_;
  NoteQueue queue_;
  OutputStage output_;
  SpscQueue<InboxEntry, kInboxCapacity> inbox_;
  Drive drive_;
  float duty_[kMotorCount]{};
  float force_n_ = 0.0f;  // the drive's achieved force along the direction (N)
  bool has_drive_ = false;
  protocol::Settings settings_{};
  protocol::Started started_{};
  Stats stats_{};

  std::uint64_t tick_ = 0;                 // the tick being (or last) processed
  std::atomic<std::uint32_t> tick_lo_{0};  // its low 32 bits, for the transport context
  std::atomic<bool> estop_pending_{false};
  std::atomic<std::uint32_t> inbox_lost_{0};  // written by the transport context only
  std::uint64_t last_host_tick_ = 0;       // arrival of the last well-formed host report (watchdog)
  std::uint64_t song_tick_ = 0;            // last seek target (informational, logged)
  std::uint32_t watchdog_ticks_ = 0;
  std::uint32_t status_period_playing_ = 1, status_period_idle_ = 1;
  std::uint32_t status_countdown_ = 1;  // ticks until the next Status (the next one included)
  std::uint32_t faults_ = protocol::fault_none;
  protocol::State state_ = protocol::State::idle;
  std::uint16_t last_seq_ = 0;             // last well-formed host report processed (done or refused)
  bool version_locked_ = false;            // a Hello of another version came last
  std::uint16_t tx_seq_ = 0;
  float last_output_ = 0.0f;
};

}  // namespace hmp::fw
