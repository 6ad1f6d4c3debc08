#pragma once
// The board seam (design §8): everything the board-independent core needs from a board, as a plain struct
// of function pointers (no virtual calls, no RTTI, no board header in the core). A board fills one in,
// constructs hmp::fw::Core with it, and then
//   - calls core.on_tick() from its tick timer interrupt (tick_hz times per second), and
//   - calls core.on_packet(report) for every 64-byte report the transport receives (HID OUT report,
//     a deframed UART packet, or an in-process call). on_packet may run in another interrupt than the
//     tick: it decodes the report and fills a lock-free single-producer/single-consumer queue;
//   - calls core.poll() from its main loop (below the tick) whenever a tick may have left work: it sends
//     the tick's reports and prepares the voices of the next notes.
// Every pointer may be null (the call is then skipped; subtick reads as 0). A board without motors leaves
// motor_output and read_encoders null: the core then skips the SPIDAR drive and only computes the
// vibration value (output).
#include <cstdint>

#include "shared/protocol/protocol.hpp"

namespace hmp::fw {

inline constexpr int kMotorCount = 8;  // SPIDAR-G6: eight strings, eight motors, eight encoders

struct BoardSeam {
  void* ctx = nullptr;  // handed back to every call

  // Tick context. The vibration sample for this tick in full-scale units, already clamped to the
  // configured limit |value| ≤ gain ≤ 1 (a board without motors shows or logs it; with motors the drive
  // turns it into duties, below).
  void (*output)(void* ctx, float value) = nullptr;

  // Background context (Core::poll). One device→host report. Must not block: return false when there is
  // no room (the report is dropped and counted in Core::Stats::tx_dropped).
  bool (*send)(void* ctx, const protocol::Report& report) = nullptr;

  // Tick context. One line of text without a newline (rate-limited by the core). May be slow
  // (semihosting): the core logs only rare events.
  void (*log)(void* ctx, const char* line) = nullptr;

  // Any context. How far the tick timer has counted since the last tick interrupt, as a fraction of the
  // tick period in 2^-32 units. If the timer has wrapped but the tick interrupt has not run yet (it is
  // pending), return 0xFFFFFFFF rather than a small value, so tick + subtick never steps back.
  std::uint32_t (*subtick)(void* ctx) = nullptr;

  // Tick context, both or neither (the drive runs only when both are set). Encoder counters of the eight
  // motors: 2048 counts per pulley turn, growing as string pays out, free to wrap (read at the start of
  // the drive's step); then the eight PWM duties in [−1, 1] the drive computed from them (positive winds
  // string in; per-motor wiring signs are the board's business).
  void (*read_encoders)(void* ctx, std::int32_t (&counts)[kMotorCount]) = nullptr;
  void (*motor_output)(void* ctx, const float (&duty)[kMotorCount]) = nullptr;

  protocol::Board id = protocol::Board::sim;  // reported in HelloReply
  std::uint8_t flags = 0;                     // protocol::BoardFlag bits, reported in HelloReply
};

}  // namespace hmp::fw
