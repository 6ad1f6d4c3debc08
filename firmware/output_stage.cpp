#include "firmware/output_stage.hpp"

#include "shared/protocol/protocol.hpp"

namespace hmp::fw {

void OutputStage::configure(std::uint32_t tick_hz, std::uint16_t ramp_in_ms, float gain) {
  gain_ = (gain >= 0.0f && gain <= 1.0f) ? gain : 0.0f;  // the protocol checks this; NaN stays silent
  ramp_ticks_ = ms_to_ticks(ramp_in_ms, tick_hz);
  ramp_step_ = ramp_ticks_ > 0 ? 1.0f / static_cast<float>(ramp_ticks_) : 1.0f;
  const std::uint32_t fade = ms_to_ticks(kFadeOutMs, tick_hz);
  fade_ticks_ = fade > 0 ? fade : 1;
}

void OutputStage::start_ramp() {
  ramp_pos_ = 0;
  fade_left_ = 0;
  silent_ = false;
}

void OutputStage::start_fade() {
  if (silent_ || fade_left_ > 0) return;
  fade_from_ = level_;
  fade_left_ = fade_ticks_;
}

void OutputStage::silence() {
  fade_left_ = 0;
  level_ = 0.0f;
  silent_ = true;
}

float OutputStage::envelope() {
  if (silent_) return 0.0f;
  if (fade_left_ > 0) {
    --fade_left_;
    level_ = fade_from_ * static_cast<float>(fade_left_) / static_cast<float>(fade_ticks_);
    if (fade_left_ == 0) silent_ = true;
    return level_;
  }
  if (ramp_pos_ < ramp_ticks_) {
    level_ = static_cast<float>(ramp_pos_) * ramp_step_;
    ++ramp_pos_;
  } else {
    level_ = 1.0f;
  }
  return level_;
}

float OutputStage::process(float y, std::uint32_t& faults) {
  const float value = y * gain_ * envelope();
  if (value >= -gain_ && value <= gain_) return value;
  // Beyond the limit, or NaN (every comparison false): clamp, keep the sign, latch the fault.
  faults |= protocol::fault_output_limit;
  if (value > 0.0f) return gain_;
  if (value < 0.0f) return -gain_;
  return 0.0f;
}

}  // namespace hmp::fw
