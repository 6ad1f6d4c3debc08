#pragma once
// WAV exports of the haptic signal (libsndfile): mono 32-bit float at the tick rate, or resampled to
// 44.1 kHz (libsamplerate, best sinc) so that people without a device can listen to it.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hmp::audio {

inline constexpr int kAudibleRateHz = 44100;
// The most 32-bit float samples a WAV file's 32-bit chunk sizes hold (4 GiB, less room for the header).
inline constexpr std::uint64_t kMaxWavSamples = (0xFFFF'FFFFull - 4096) / 4;

// BadInput (naming the file) for more than kMaxWavSamples samples.
void write_wav(const std::string& path, std::span<const float> samples, int rate_hz, bool force);
// Band-limited resampling; the result stays within [−1, 1] (the few-percent Gibbs overshoot of the
// sinc filter at steps is clamped so a player never clips).
std::vector<float> resample(std::span<const float> samples, int from_hz, int to_hz);

}  // namespace hmp::audio
