#include "host/export/signal_export.hpp"

#include <cstdio>

#include "host/common/error.hpp"
#include "host/audio/wav_file.hpp"
#include "host/output/output_file.hpp"

namespace hmp::exporting {

namespace {
std::string format_of(const SignalExport& e) { return e.path == "-" ? "csv" : output::extension_of(e.path); }

void write_csv(std::FILE* out, std::span<const float> samples, std::uint64_t first_tick, std::uint32_t tick_hz) {
  std::fputs("t_s,value\n", out);
  const double period = 1.0 / tick_hz;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    std::fprintf(out, "%.9g,%.9g\n", static_cast<double>(first_tick + i) * period, static_cast<double>(samples[i]));
  }
}
}  // namespace

bool is_signal_export(const std::string& path) {
  const std::string fmt = format_of({path});
  return fmt == "csv" || fmt == "wav" || fmt == "png";
}

void check_export(const SignalExport& e) {
  const std::string fmt = format_of(e);
  if (!is_signal_export(e.path)) throw BadInput("--out " + e.path + ": use a .csv, .wav or .png file");
  if (e.audible && fmt != "wav") throw BadInput("--audible needs a .wav output");
  output::check_writable(e.path, e.force);
}

void export_signal(const SignalExport& e, std::span<const float> samples, std::span<const output::PlotNote> notes,
                   const output::PlotSpec& spec) {
  const std::string fmt = format_of(e);
  if (fmt == "csv") {
    output::FilePtr f = output::open_for_writing(e.path, e.force);
    write_csv(f.get(), samples, spec.first_tick, spec.tick_hz);
    output::close_output(f);
  } else if (fmt == "wav") {
    if (e.audible) {
      audio::write_wav(e.path, audio::resample(samples, static_cast<int>(spec.tick_hz), audio::kAudibleRateHz),
                       audio::kAudibleRateHz, e.force);
    } else {
      audio::write_wav(e.path, samples, static_cast<int>(spec.tick_hz), e.force);
    }
  } else {
    output::write_signal_png(e.path, samples, notes, spec, e.force);
  }
}

}  // namespace hmp::exporting
