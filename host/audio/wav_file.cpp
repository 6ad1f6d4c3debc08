#include "host/audio/wav_file.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "host/audio/audio_backend.hpp"
#include "host/common/error.hpp"
#include "host/output/output_file.hpp"

namespace hmp::audio {
namespace {

// libsndfile and libsamplerate live in the audio module, loaded on first use.
const AudioBackend& backend_for(const std::string& what) {
  std::string why;
  const AudioBackend* backend = audio_backend(&why);
  if (backend == nullptr) throw BadInput(what + ": needs the audio module, which is not available (" + why + ")");
  return *backend;
}

}  // namespace

void write_wav(const std::string& path, std::span<const float> samples, int rate_hz, bool force) {
  output::check_writable(path, force);
  if (samples.size() > kMaxWavSamples) {
    throw BadInput(fmt::format("{}: {} samples at {} Hz, more than a WAV file holds ({})", path, samples.size(),
                               rate_hz, kMaxWavSamples));
  }
  const std::span<const float> channels[] = {samples};
  const AudioBackend& backend = backend_for(path);
  output::StagedOutput staged(path);  // libsndfile writes PATH.part, renamed to PATH once whole
  if (const std::string error = backend.write_wav(staged.part(), rate_hz, channels); !error.empty()) {
    throw BadInput(path + ": cannot write WAV: " + error);
  }
  staged.commit();
}

std::vector<float> resample(std::span<const float> samples, int from_hz, int to_hz) {
  std::string error;
  std::vector<float> out = backend_for("resampling").resample(samples, from_hz, to_hz, error);
  if (!error.empty()) throw std::runtime_error("resampling failed: " + error);
  for (float& v : out) v = std::clamp(v, -1.0f, 1.0f);
  return out;
}

}  // namespace hmp::audio
