// hmp tone — one note, for inspection and tests (design §3).
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "host/audio/wav_file.hpp"
#include "host/cli/commands.hpp"
#include "host/common/error.hpp"
#include "host/haptics/adsr_option.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/haptics/signal_renderer.hpp"
#include "host/export/signal_export.hpp"
#include "shared/synth/frequency.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::cli {

namespace {

struct ToneOptions {
  double freq_hz = std::numeric_limits<double>::quiet_NaN();
  double amp = std::numeric_limits<double>::quiet_NaN();
  double ms = std::numeric_limits<double>::quiet_NaN();
  std::optional<std::string> instrument;
  std::optional<std::string> adsr;
  std::string out = "-";
  std::uint32_t tick_hz = synth::kNominalTickHz;
  double end_fade_ms = 2.0;
  bool force = false;
};

int run_tone(const ToneOptions& o) {
  if (!std::isfinite(o.freq_hz) || o.freq_hz <= 0) throw BadInput("--freq: must be a positive number of Hz");
  const double alias_limit = haptics::kHighestFreqFraction * o.tick_hz;
  if (o.freq_hz >= alias_limit) {
    throw BadInput(fmt::format("--freq {:g}: must be below {:g} × tick rate = {:g} Hz (aliasing)", o.freq_hz,
                               haptics::kHighestFreqFraction, alias_limit));
  }
  if (o.freq_hz > synth::kFreqMaxHz) throw BadInput("--freq: above the device's top frequency 4096 Hz");
  if (!std::isfinite(o.amp) || o.amp <= 0 || o.amp > 1) throw BadInput("--amp: must be in (0, 1]");
  if (!std::isfinite(o.ms) || o.ms < 0 || o.ms > 24.0 * 3600e3) throw BadInput("--ms: must be in [0, 86400000]");
  if (!std::isfinite(o.end_fade_ms) || o.end_fade_ms < 0 || o.end_fade_ms > 1000) {
    throw BadInput("--end-fade-ms: must be in [0, 1000]");
  }
  if (o.instrument.has_value() == o.adsr.has_value()) throw BadInput("give exactly one of --instrument or --adsr");

  haptics::UserPreset preset;
  preset.adsr = o.instrument ? haptics::builtin_by_name(*o.instrument) : haptics::parse_adsr(*o.adsr);

  // design §6 ticks: N = max(1, round(D/T)), one sample each: at most what one WAV file holds.
  const double ticks = std::max(1.0, std::round(o.ms * o.tick_hz / 1000.0));
  if (ticks > static_cast<double>(audio::kMaxWavSamples)) {
    throw BadInput(
        fmt::format("--ms {:.15g} at --tick-hz {}: {:.0f} samples, more than the {} of one export (a WAV file's "
                    "limit)",
                    o.ms, o.tick_hz, ticks, audio::kMaxWavSamples));
  }
  const auto n_ticks = static_cast<std::uint32_t>(ticks);
  synth::Note note;
  note.start_tick = 0;
  note.duration_ticks = n_ticks;
  note.freq_q20 = synth::freq_to_q20(o.freq_hz);
  note.amp_q16 = synth::amp_to_q16(o.amp);
  note.preset = preset.slot;

  haptics::RenderSettings settings;
  settings.synth.tick_hz = o.tick_hz;
  settings.synth.end_fade_ms = static_cast<float>(o.end_fade_ms);
  const exporting::SignalExport out{o.out, false, o.force};
  exporting::check_export(out);  // before the (possibly long) render
  const auto samples = haptics::render_signal({&note, 1}, {&preset, 1}, settings, 0, n_ticks);
  output::PlotSpec spec;
  spec.title = fmt::format("hmp tone: {:g} Hz, amplitude {:g}, {:g} ms, envelope {}", o.freq_hz, o.amp, o.ms,
                           o.instrument ? *o.instrument : "--adsr " + *o.adsr);
  spec.tick_hz = o.tick_hz;
  const output::PlotNote plot_note{0.0, static_cast<double>(n_ticks) / o.tick_hz, 60};
  exporting::export_signal(out, samples, {&plot_note, 1}, spec);
  return kExitOk;
}

}  // namespace

void register_tone(CLI::App& app, Registry& registry) {
  auto opts = std::make_shared<ToneOptions>();
  CLI::App* cmd = app.add_subcommand("tone", "Render one note (frequency, amplitude, envelope) as the device would");
  cmd->add_option("--freq", opts->freq_hz, "Frequency in Hz (below 0.45 × tick rate)")->required();
  cmd->add_option("--amp", opts->amp, "Peak amplitude, linear in (0, 1] of full scale")->required();
  cmd->add_option("--ms", opts->ms, "Note duration in ms")->required();
  auto* inst = cmd->add_option("--instrument", opts->instrument, "Envelope preset: " + haptics::builtin_names());
  auto* adsr =
      cmd->add_option("--adsr", opts->adsr, "Custom envelope: attack=MS,decay=MS,sustain=PCT,release=MS,final=PCT");
  inst->excludes(adsr);
  cmd->add_option("--out", opts->out,
                  "Output: FILE.csv, FILE.wav (float, tick rate) or FILE.png (plot); '-' = CSV on stdout")
      ->capture_default_str();
  cmd->add_option("--tick-hz", opts->tick_hz, "Device tick rate in Hz")
      ->capture_default_str()
      ->check(CLI::Range(100u, 100000u));
  cmd->add_option("--end-fade-ms", opts->end_fade_ms, "Fade at the note's end in ms (0 = paper-exact)")
      ->capture_default_str();
  cmd->add_flag("-f,--force", opts->force, "Overwrite an existing output file");
  cmd->callback([opts, &registry] { registry.set([opts] { return run_tone(*opts); }); });
}

}  // namespace hmp::cli
