// hmp envelope measure: the envelope of the sound each GM program makes, fitted to the paper's Eq. 9–10
// (host/measure/), printed, written as presets `--config` reads, and plotted over the sound.
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "host/audio/soundfont.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/measure/measure.hpp"
#include "host/midi/gm.hpp"
#include "host/output/output_file.hpp"
#include "host/output/trace_plot.hpp"

namespace hmp::cli {

namespace {

struct EnvelopeOptions {
  std::optional<std::string> soundfont, out, plot_dir;
  std::optional<int> program;
  bool all = false;
  std::optional<int> key;
  int velocity = 100;
  bool force = false;
};

std::string preset_name(std::uint8_t program) { return fmt::format("measured-{:03}", program); }

std::string seconds(double s) { return std::isnan(s) ? "    -" : fmt::format("{:5.3f}", s); }

std::string soundfont_path(const EnvelopeOptions& o) {
  if (o.soundfont) {
    check_soundfont_option(*o.soundfont);
    return *o.soundfont;
  }
  const auto found = audio::find_soundfont();
  if (!found) throw BadInput("no General MIDI SoundFont found (install fluid-soundfont-gm, or give --soundfont FILE)");
  return *found;
}

void write_presets(const std::string& path, bool force, const std::vector<measure::Measured>& ms,
                   const measure::MeasureOptions& mo) {
  output::FilePtr f = output::open_for_writing(path, force);
  std::string text = fmt::format(
      "# Envelopes measured by `hmp envelope measure` from {} (key {}, velocity {}):\n"
      "# each preset is the paper's Eq. 9-10 fitted to one note's sound. Use with --config {} and\n"
      "# --envelope measured (or auto: instruments Table 1 lacks get theirs).\n",
      mo.soundfont, mo.key, mo.velocity, path == "-" ? std::string("THIS_FILE") : path);
  for (const measure::Measured& m : ms) {
    if (!m.stages.sounded) continue;
    const envelope::Adsr& a = m.preset;
    text += fmt::format("\n[presets.{}]  # {}: RMS error {:.3f} of full scale\n", preset_name(m.program),
                        midi::gm_program_name(m.program), m.rms_error);
    text += fmt::format(
        "attack_ms = {:.1f}\ndecay_ms = {:.1f}\nrelease_ms = {:.1f}\nsustain_pct = {:.2f}\nfinal_pct = {:.2f}\n",
        a.attack_ms, a.decay_ms, a.release_ms, 100.0 * double(a.sustain), 100.0 * double(a.final_ratio));
  }
  text += "\n[measured]\n";
  for (const measure::Measured& m : ms) {
    if (m.stages.sounded) text += fmt::format("\"{}\" = \"{}\"\n", m.program, preset_name(m.program));
  }
  std::fputs(text.c_str(), f.get());
  output::close_output(f);
}

void plot(const std::string& dir, bool force, const measure::Measured& m) {
  std::vector<float> sound, fit(m.held.amplitude.size(), 0.0f);
  for (double a : m.held.amplitude) sound.push_back(static_cast<float>(a / m.stages.peak));
  const double duration = measure::note_duration(m.held, m.stages, m.preset);
  for (const measure::CurvePoint& p : measure::preset_curve(m.held, m.stages, m.preset, duration)) {
    fit[p.index] = static_cast<float>(p.value);
  }
  output::TracePlotSpec spec;
  spec.title = fmt::format("{} ({}): sound and Eq. 9-10 fit, RMS error {:.3f}", midi::gm_program_name(m.program),
                           m.program, m.rms_error);
  spec.y_label = "amplitude (peak = 1)";
  spec.rate_hz = 1.0 / m.held.step_s;
  spec.width = 1200;
  spec.height = 500;
  const std::vector<output::Trace> traces = {{"sound (FluidSynth)", sound, 0.2, 0.4, 0.8},
                                             {"Eq. 9-10 preset", fit, 0.85, 0.3, 0.1}};
  output::write_traces_png(fmt::format("{}/program-{:03}.png", dir, m.program), traces, spec, force);
}

int run_measure(const EnvelopeOptions& o) {
  if (o.program && o.all) throw BadInput("--program and --all: give one of them");
  measure::MeasureOptions mo;
  mo.soundfont = soundfont_path(o);
  mo.key = static_cast<std::uint8_t>(o.key.value_or(60));
  mo.key_fallback = !o.key;
  mo.velocity = static_cast<std::uint8_t>(o.velocity);
  if (o.program)
    mo.programs = {static_cast<std::uint8_t>(*o.program)};
  else if (o.all)
    for (int p = 0; p < 128; ++p) mo.programs.push_back(static_cast<std::uint8_t>(p));
  else
    for (const midi::Table1Instrument& i : midi::kTable1Instruments) mo.programs.push_back(i.typical);
  // FluidSynth would play some other preset for a program the SoundFont lacks: those are left out.
  const std::set<std::uint8_t> present = audio::soundfont_programs(mo.soundfont);
  std::string absent;
  std::vector<std::uint8_t> playable;
  for (std::uint8_t p : mo.programs) {
    if (present.count(p))
      playable.push_back(p);
    else
      absent += (absent.empty() ? "" : ", ") + std::to_string(p);
  }
  mo.programs = std::move(playable);
  if (mo.programs.empty()) {
    throw BadInput(fmt::format("{}: no preset for program {} in bank 0", mo.soundfont, absent));
  }
  // Every output is checked before the work starts.
  if (o.out) output::check_writable(*o.out, o.force);
  if (o.plot_dir) {
    struct stat st {};
    if (::stat(o.plot_dir->c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
      throw BadInput("--plot " + *o.plot_dir + ": not a directory");
    }
  }
  const std::vector<measure::Measured> ms =
      measure::measure_programs(mo, [](const std::string& what) { std::fprintf(stderr, "%s…\n", what.c_str()); });

  std::string silent;
  int sounded = 0;
  for (const measure::Measured& m : ms) {
    if (m.stages.sounded)
      ++sounded;
    else
      silent += (silent.empty() ? "" : ", ") + std::to_string(m.program);
  }
  if (sounded == 0 || (o.program && !silent.empty())) {
    throw BadInput(fmt::format("program {}: the note (key {}, velocity {}) never sounds in {}", silent, mo.key,
                               o.velocity, mo.soundfont));
  }
  // The table is for people; with --out - the presets go to standard output alone, for a program to read.
  std::FILE* const table = o.out && *o.out == "-" ? stderr : stdout;
  fmt::print(table, "{}: key {} ({:.1f} Hz), velocity {}, held {:g} s\n", mo.soundfont, mo.key, measure::key_hz(mo.key),
             o.velocity, mo.hold_s);
  fmt::print(table, "{:>4}  {:<20} {:>3} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} | {:>6} {:>6} {:>5} {:>6} {:>4} {:>6}\n",
             "#", "program", "key", "delay", "attack", "hold", "decay", "sust.", "rel.", "A ms", "Dc ms", "s %", "R ms",
             "r %", "RMS");
  for (const measure::Measured& m : ms) {
    if (!m.stages.sounded) continue;
    const measure::Stages& s = m.stages;
    const envelope::Adsr& a = m.preset;
    fmt::print(
        table,
        "{:>4}  {:<20.20} {:>3} {:>6} {:>6} {:>6} {:>6} {:>6.3f} {:>6} | {:>6.1f} {:>6.1f} {:>5.1f} {:>6.1f} {:>4.1f} "
        "{:>6.3f}\n",
        m.program, midi::gm_program_name(m.program), m.key, seconds(s.delay_s), seconds(s.attack_s), seconds(s.hold_s),
        seconds(s.decay_s), s.sustain, seconds(s.release_s), a.attack_ms, a.decay_ms, 100.0 * double(a.sustain),
        a.release_ms, 100.0 * double(a.final_ratio), m.rms_error);
  }
  fmt::print(table,
             "Left: FluidSynth's stages in s (decay, release: the time to fall 96 dB; sustain: level/peak).\n"
             "Right: the paper's Eq. 9-10 fitted; RMS: its error against the sound, full scale = the peak.\n");
  if (!absent.empty()) std::fprintf(stderr, "warning: not in this SoundFont, left out: program %s\n", absent.c_str());
  if (!silent.empty())
    std::fprintf(stderr, "warning: never sounds in this SoundFont, left out: program %s\n", silent.c_str());
  if (o.out) {
    write_presets(*o.out, o.force, ms, mo);
    std::fprintf(stderr, "wrote %s (%d preset(s))\n", *o.out == "-" ? "standard output" : o.out->c_str(), sounded);
  }
  if (o.plot_dir) {
    for (const measure::Measured& m : ms) {
      if (m.stages.sounded) plot(*o.plot_dir, o.force, m);
    }
    std::fprintf(stderr, "wrote %d plot(s) to %s\n", sounded, o.plot_dir->c_str());
  }
  return kExitOk;
}

}  // namespace

void register_envelope(CLI::App& app, Registry& registry) {
  CLI::App* cmd = app.add_subcommand("envelope", "Envelopes of the sound that is heard (measure)");
  cmd->require_subcommand(1);
  auto o = std::make_shared<EnvelopeOptions>();
  CLI::App* m = cmd->add_subcommand(
      "measure", "Render a note of each program with FluidSynth, fit the paper's Eq. 9-10 to its envelope");
  m->add_option("--soundfont", o->soundfont, "SoundFont (.sf2/.sf3) (default: the GM one installed)");
  m->add_option("--program", o->program, "One GM program 0-127 (default: Table 1's eight instruments)")
      ->check(CLI::Range(0, 127));
  m->add_flag("--all", o->all, "All 128 GM programs");
  m->add_option("--key", o->key, "MIDI key of the note (default 60, middle C; 1-2 octaves away where it is silent)")
      ->check(CLI::Range(0, 127));
  m->add_option("--velocity", o->velocity, "Velocity 1-127 (default 100)")->check(CLI::Range(1, 127));
  m->add_option("--out", o->out, "Write the presets as TOML that --config reads");
  m->add_option("--plot", o->plot_dir, "Folder for one PNG per program: the sound's envelope over the fit");
  m->add_flag("--force", o->force, "Replace existing output files");
  m->callback([o, &registry] { registry.set([o] { return run_measure(*o); }); });
}

}  // namespace hmp::cli
