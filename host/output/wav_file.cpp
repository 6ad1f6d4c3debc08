#include "host/output/wav_file.hpp"

#include <samplerate.h>
#include <sndfile.h>

#include <algorithm>
#include <stdexcept>

#include "host/common/error.hpp"
#include "host/output/output_file.hpp"

namespace hmp::output {

void write_wav(const std::string& path, std::span<const float> samples, int rate_hz, bool force) {
  check_writable(path, force);
  SF_INFO info{};
  info.samplerate = rate_hz;
  info.channels = 1;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  if (!f) throw BadInput(path + ": cannot write WAV: " + sf_strerror(nullptr));
  const auto n = static_cast<sf_count_t>(samples.size());
  const sf_count_t written = sf_write_float(f, samples.data(), n);
  const int close_err = sf_close(f);
  if (written != n || close_err != 0) throw std::runtime_error(path + ": WAV write failed");
}

std::vector<float> resample(std::span<const float> samples, int from_hz, int to_hz) {
  if (samples.empty()) return {};
  const double ratio = static_cast<double>(to_hz) / from_hz;
  std::vector<float> out(static_cast<std::size_t>(static_cast<double>(samples.size()) * ratio) + 64);
  SRC_DATA data{};
  data.data_in = samples.data();
  data.input_frames = static_cast<long>(samples.size());
  data.data_out = out.data();
  data.output_frames = static_cast<long>(out.size());
  data.src_ratio = ratio;
  data.end_of_input = 1;
  const int err = src_simple(&data, SRC_SINC_BEST_QUALITY, 1);
  if (err != 0) throw std::runtime_error(std::string("resampling failed: ") + src_strerror(err));
  out.resize(static_cast<std::size_t>(data.output_frames_gen));
  for (float& v : out) v = std::clamp(v, -1.0f, 1.0f);
  return out;
}

}  // namespace hmp::output
