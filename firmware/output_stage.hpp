#pragma once
// The last step of the tick before the board (design §8 safety): ramp-in at the start of play, fade-out
// on pause/stop/watchdog, immediate silence on emergency stop, gain, and the clamp to the configured
// limit |value| ≤ gain. The clamp is the last line of defence: it also catches a NaN or an
// out-of-range sample from a bug upstream, which latches fault_output_limit.
#include <cstdint>

namespace hmp::fw {

// How long a fade-out takes. design §8 demands silence within 20 ms of the watchdog tripping; 15 ms
// leaves room for the tick on which the trip is noticed.
inline constexpr std::uint32_t kFadeOutMs = 15;

// ms → ticks at tick_hz, rounded down (exact for the 1 kHz and 10 kHz builds).
constexpr std::uint32_t ms_to_ticks(std::uint32_t ms, std::uint32_t tick_hz) {
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(ms) * tick_hz / 1000u);
}

class OutputStage {
 public:
  void configure(std::uint32_t tick_hz, std::uint16_t ramp_in_ms, float gain);

  void start_ramp();  // from silence: rise linearly from 0 to full over ramp_in_ms
  void start_fade();  // fall linearly from the present level to 0 over kFadeOutMs, then silent
  void silence();     // 0 from the next sample on, until start_ramp()

  bool fading() const { return fade_left_ > 0; }
  bool silent() const { return silent_; }
  float limit() const { return gain_; }

  // One tick: the engine's sample in [−1, 1] → the value for the board. Adds fault bits to `faults`.
  float process(float y, std::uint32_t& faults);

 private:
  float envelope();  // the present ramp/fade factor in [0, 1], advanced one tick

  float gain_ = 1.0f;
  std::uint32_t ramp_ticks_ = 0, ramp_pos_ = 0;
  float ramp_step_ = 0.0f;  // 1 / ramp_ticks
  std::uint32_t fade_ticks_ = 1, fade_left_ = 0;
  float fade_from_ = 0.0f;  // level when the fade began
  float level_ = 0.0f;      // the last factor applied (where a fade starts from)
  bool silent_ = true;
};

}  // namespace hmp::fw
