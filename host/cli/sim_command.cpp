// hmp sim SONG --track T [--out FILE.csv|.png] — plays one track on the simulated device with its plant
// (design §12, §13 `sim`) and shows the force the strings actually put on the grip next to the vibration
// the firmware was asked for: the fidelity of the whole chain (synthesis → drive → motors → strings).
// The plant's physics come from the config's [plant] table and --string-stiffness, --integrator,
// --max-step. With --work-precision the passage's duties are recorded and replayed under every integrator
// and CVODE, and the error of each against a tight CVODE reference is printed (or written as CSV / PNG)
// against its run time: a user checks the simulator on their own device's parameters.
// The song goes through the same haptic-track builder as `hmp render` and reaches the device as protocol
// reports (Hello, Settings, Preset, Notes within the device's credit, Play, Syncs), exactly as over USB.
#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <cstdio>
#include <map>

#include <fmt/format.h>

#include "host/cli/commands.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/progress.hpp"
#include "host/midi/gm.hpp"
#include "host/output/output_file.hpp"
#include "host/output/trace_plot.hpp"
#include "host/player/note_batcher.hpp"
#include "host/config/config.hpp"
#include "host/output/loglog_plot.hpp"
#include "host/simulate/fidelity.hpp"
#include "host/simulate/plant_config.hpp"
#include "host/simulate/work_precision.hpp"
#include "host/simulate/sim_host.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/synth/engine.hpp"

namespace hmp::cli {

namespace {

struct SimCliOptions {
  std::string song;
  std::string track;
  std::string out = "-";
  std::optional<double> from_s, to_s;
  bool force = false;
  std::optional<double> peak_force_n;  // default: the config's [device] peak_force_n, else 1 N
  bool plain_drive = false;
  bool work_precision = false;
  simulate::PlantOverrides plant;
  HapticCliOptions haptic;
};

void write_csv(const SimCliOptions& o, const std::vector<simulate::ForceSample>& samples, double t0,
               std::uint32_t tick_hz) {
  output::FilePtr f = output::open_for_writing(o.out, o.force);
  std::fputs("t_s,commanded_n,actual_n,reported_n,min_tension_n,max_tension_n\n", f.get());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const simulate::ForceSample& s = samples[i];
    std::fprintf(f.get(), "%.6f,%.6g,%.6g,%.6g,%.6g,%.6g\n", t0 + static_cast<double>(i) / tick_hz,
                 static_cast<double>(s.commanded), static_cast<double>(s.actual), static_cast<double>(s.reported),
                 static_cast<double>(s.min_tension), static_cast<double>(s.max_tension));
  }
  output::close_output(f);
}

// A text field as RFC 4180 has it: in double quotes, its quotes doubled, where it holds a comma, a quote or
// a line break (CVODE's messages have commas).
std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void write_work_precision_csv(const SimCliOptions& o, const simulate::WorkPrecision& wp) {
  output::FilePtr f = output::open_for_writing(o.out, o.force);
  std::fputs(
      "integrator,steps_per_tick,rtol,default,ok,force_error_rel,finger_force_error_rel,band_force_error_rel,"
      "realtime_factor,reference_convergence_force,reference_convergence_finger,reference_convergence_band,"
      "tick_force_error_rel,tick_finger_force_error_rel,derivatives,failure\n",
      f.get());
  // A value not measured (the band of a method other than the default) is an empty field.
  const auto value = [](double v, const char* format) {
    return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string();
  };
  for (const simulate::WorkPrecisionPoint& p : wp.points) {
    std::fprintf(f.get(), "%s,%d,%g,%d,%d,%.4g,%.4g,%s,%.4g,%.3g,%.3g,%s,%s,%s,%s,%s\n", p.integrator.c_str(),
                 p.steps_per_tick, p.rtol, p.is_default ? 1 : 0, p.ok() ? 1 : 0, p.error.force, p.error.finger_force,
                 value(p.error.band_force, "{:.4g}").c_str(), p.realtime_factor, wp.reference_convergence.force,
                 wp.reference_convergence.finger_force, value(wp.reference_convergence.band_force, "{:.3g}").c_str(),
                 value(p.tick_error.force, "{:.4g}").c_str(), value(p.tick_error.finger_force, "{:.4g}").c_str(),
                 p.ok() ? std::to_string(p.derivatives).c_str() : "", csv_text(p.failure).c_str());
  }
  output::close_output(f);
}

// An error below ten times its reference's own uncertainty is not resolved: shown as an upper bound.
std::string resolved(const simulate::WorkPrecision& wp, double error, double convergence) {
  return wp.claimed(error, convergence) ? fmt::format("{:.3g}%", 100 * error)
                                        : fmt::format("< {:.2g}%", 1000 * convergence);
}

void print_work_precision(const simulate::WorkPrecision& wp) {
  std::printf("reference: cvode, its change on halving the tolerance %.2g (string force), %.2g (finger force)\n",
              wp.reference_convergence.force, wp.reference_convergence.finger_force);
  std::printf("%-22s %9s %14s %14s %14s %10s %12s\n", "integrator", "steps/tick", "string force", "finger force",
              "< 1 kHz", "x realtime", "derivatives");
  for (const simulate::WorkPrecisionPoint& p : wp.points) {
    const std::string name = p.integrator + (p.is_default ? " (default)" : "");
    const std::string steps =
        p.integrator == "cvode" ? fmt::format("rtol {:g}", p.rtol) : std::to_string(p.steps_per_tick);
    if (!p.ok()) {
      std::printf("%-22s %9s  %s\n", name.c_str(), steps.c_str(), p.failure.c_str());
      continue;
    }
    const simulate::TraceError& c = wp.reference_convergence;
    const std::string band = std::isfinite(p.error.band_force) ? resolved(wp, p.error.band_force, c.band_force) : "";
    std::printf("%-22s %9s %14s %14s %14s %10.1f %12ld\n", name.c_str(), steps.c_str(),
                resolved(wp, p.error.force, c.force).c_str(),
                resolved(wp, p.error.finger_force, c.finger_force).c_str(), band.c_str(), p.realtime_factor,
                p.derivatives);
  }
  if (!wp.tick_reference_error.empty())
    std::printf("default over one tick: not measured (the one-tick reference failed: %s)\n",
                wp.tick_reference_error.c_str());
  for (const simulate::WorkPrecisionPoint& p : wp.points) {
    if (!p.is_default || !std::isfinite(p.tick_error.force)) continue;
    const simulate::TraceError& c = wp.tick_reference_convergence;
    std::printf(
        "default over one tick (every %dth tick taken again by cvode from its state): %s string force, "
        "%s finger force\n",
        simulate::kTickSampleEvery, resolved(wp, p.tick_error.force, c.force).c_str(),
        resolved(wp, p.tick_error.finger_force, c.finger_force).c_str());
  }
}

void draw_work_precision(const SimCliOptions& o, const simulate::WorkPrecision& wp, const std::string& title) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<output::LabelledPoint> grip, finger;
  for (const simulate::WorkPrecisionPoint& p : wp.points) {
    const double cpu_per_second = p.ok() ? 1.0 / p.realtime_factor : nan;
    grip.push_back({p.integrator, p.is_default, cpu_per_second, p.ok() ? p.error.force : nan});
    finger.push_back({p.integrator, p.is_default, cpu_per_second, p.ok() ? p.error.finger_force : nan});
  }
  output::LogLogPlotSpec spec;
  spec.title = title;
  spec.x_label = "CPU seconds per simulated second";
  spec.y_label = "relative error against CVODE (RMS)";
  spec.x_guides = {{1.0, "real time"}};
  output::write_loglog_png(
      o.out, {{"string force on the grip", output::series_of(grip)}, {"finger force", output::series_of(finger)}}, spec,
      o.force);
}

int run_sim(const SimCliOptions& o) {
  const std::string fmt_out = o.out == "-" ? "csv" : output::extension_of(o.out);
  if (fmt_out != "csv" && fmt_out != "png") throw BadInput("--out " + o.out + ": use a .csv or .png file");
  const auto most_n = static_cast<double>(protocol::kMaxPeakForceN);
  if (o.peak_force_n && !(*o.peak_force_n > 0 && *o.peak_force_n <= most_n))
    throw BadInput(fmt::format("--peak-force: must be in (0, {:g}] N", most_n));
  sim::SimOptions so;
  so.plant = sim::PlantOptions{};
  // Each config's [plant] and [device] in turn (later files override earlier ones), then the command line.
  protocol::Settings settings;
  for (const std::string& path : o.haptic.config_paths) {
    const config::Config c = config::load(path);
    simulate::apply_plant_settings(c.plant, {}, so.plant->params);
    if (c.peak_force_n) settings.peak_force_n = static_cast<float>(*c.peak_force_n);
    if (c.direction)
      for (std::size_t i = 0; i < 3; ++i) settings.direction[i] = static_cast<float>((*c.direction)[i]);
  }
  simulate::apply_plant_settings({}, o.plant, so.plant->params);
  if (o.peak_force_n) settings.peak_force_n = static_cast<float>(*o.peak_force_n);
  const haptics::HapticOptions opts = resolve(o.haptic);
  output::check_writable(o.out, o.force);

  const TrackWindow w = load_track_window(o.song, o.track, opts, o.from_s, o.to_s, warn_on_stderr);
  const midi::ReadResult& r = w.read;
  const std::uint32_t track = w.track;
  const haptics::HapticTrack& ht = w.haptic;
  const std::uint64_t first = w.first_tick, end = w.end_tick;
  if (end - first > 600ull * opts.tick_hz) throw BadInput("--from/--to: at most 600 s of simulation at a time");

  if (o.work_precision && static_cast<double>(end - first) > simulate::kMaxWorkPrecisionSeconds * opts.tick_hz) {
    throw BadInput(fmt::format("--work-precision: the passage is {:.1f} s; pick at most {:g} s with --from/--to",
                               static_cast<double>(end - first) / opts.tick_hz, simulate::kMaxWorkPrecisionSeconds));
  }
  so.tick_hz = opts.tick_hz;
  so.drive.compensator.enabled = !o.plain_drive;
  sim::SimDevice dev(so);
  simulate::SimHost host(dev);
  settings.policy = static_cast<protocol::PolicyCode>(opts.polyphony);
  settings.end_fade_ms = static_cast<float>(opts.end_fade_ms);
  host.send(protocol::make(protocol::Type::hello, 0));
  protocol::Message m = protocol::make(protocol::Type::settings, 0);
  m.settings = settings;
  host.send(m);
  for (const haptics::UserPreset& p : ht.uploads) {
    m = protocol::make(protocol::Type::preset, 0);
    m.preset.slot = p.slot;
    m.preset.adsr = p.adsr;
    host.send(m);
  }
  m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = protocol::TransportOp::play;
  host.send(m);
  // The window starts once the ramp-in is over (plus a margin for the first notes to arrive).
  const std::uint64_t base = dev.tick() + (static_cast<std::uint64_t>(settings.ramp_in_ms) + 100) * opts.tick_hz / 1000;
  const std::vector<synth::Note> notes = simulate::window_notes(ht, first, end, base);
  const std::uint64_t lookahead = opts.tick_hz / 5, sync_period = opts.tick_hz / 10;
  const sim::plant::Vec3d direction{static_cast<double>(settings.direction[0]),
                                    static_cast<double>(settings.direction[1]),
                                    static_cast<double>(settings.direction[2])};  // (0, 1, 0) unless configured

  simulate::PlantScene replay;  // --work-precision: the passage's input, from the plant's reset on
  replay.name = "passage";
  replay.params = so.plant->params;
  replay.bias_tension = so.plant->bias_tension;
  replay.drive.tick_s = 1.0 / opts.tick_hz;
  std::vector<simulate::ForceSample> samples;
  samples.reserve(end - first);
  std::size_t cursor = 0;
  ProgressBar bar("simulating");
  for (std::uint64_t since_sync = 0; dev.tick() + 1 < base + (end - first); ++since_sync) {
    host.collect();
    // Only what the device's inbox takes now: SimHost::send would run the device's ticks until it had
    // room (a NAKed USB transfer), and those ticks would be missing from the samples. The rest goes on
    // the next tick, as a host's would after a NAK.
    const auto room = [&] { return dev.core().inbox_has_room(); };
    while (cursor < notes.size() && notes[cursor].start_tick <= dev.tick() + lookahead && host.credit() > 0 && room()) {
      m = protocol::Message{};
      cursor += player::make_report(std::span(notes).subspan(cursor), m);
      host.send(m);
    }
    if (since_sync >= sync_period && room()) {
      host.send(protocol::make(protocol::Type::sync, 0));
      since_sync = 0;
    }
    const sim::plant::PlantOutput before = dev.plant()->output();  // the force at the start of this tick
    dev.advance(1);
    if (o.work_precision) {  // the duties this tick drove the plant with, for the replays
      std::array<double, 8> d{};
      for (int i = 0; i < 8; ++i) d[static_cast<std::size_t>(i)] = static_cast<double>(dev.duties()[i]);
      replay.drive.duty.push_back(d);
      replay.drive.anchor.push_back(so.plant->params.finger.anchor);
    }
    if (dev.tick() < base) continue;
    simulate::ForceSample s;
    s.commanded = dev.last_output() * settings.peak_force_n;
    s.actual = static_cast<float>(spidar::dot(before.string_force, direction));
    s.reported = dev.core().status().force_n;
    s.min_tension = static_cast<float>(*std::min_element(std::begin(before.tension), std::end(before.tension)));
    s.max_tension = static_cast<float>(*std::max_element(std::begin(before.tension), std::end(before.tension)));
    samples.push_back(s);
    bar.update(samples.size(), end - first);
    if (dev.plant_unstable()) break;
  }
  host.collect();
  if (dev.plant_unstable()) {
    const double at_s = static_cast<double>(samples.size()) / opts.tick_hz;
    const sim::plant::Method method = so.plant->params.stepper.method;
    // The default integrator is stable on any plant it can represent: there the values are at fault.
    if (method == simulate::default_method()) {
      throw BadInput(
          fmt::format("the plant went unstable at {:.3f} s under the default integrator: its values "
                      "([plant], --string-stiffness) are beyond what can be simulated (a mass or inertia "
                      "near zero?)",
                      at_s));
    }
    throw std::runtime_error(
        fmt::format("the plant simulation went unstable at {:.3f} s: integrator {} is past its "
                    "stable step (use {})",
                    at_s, sim::plant::method_name(method), sim::plant::method_name(simulate::default_method())));
  }
  const midi::Track& t = r.song.tracks[track];
  if (o.work_precision) {
    const double seconds = static_cast<double>(replay.drive.duty.size()) / opts.tick_hz;
    std::fprintf(stderr, "work-precision: %.2f s of the plant's input, replayed under every integrator and CVODE\n",
                 seconds);
    ProgressBar wp_bar("work-precision");
    simulate::WorkPrecisionOptions wo;
    std::size_t total_runs = 0;
    wo.progress = [&](std::string_view, std::size_t done, std::size_t total) {
      wp_bar.update(done, total);
      total_runs = total;
    };
    const simulate::WorkPrecision wp = simulate::work_precision(replay, wo);
    wp_bar.update(total_runs, total_runs);
    if (o.out == "-")
      print_work_precision(wp);
    else if (fmt_out == "csv")
      write_work_precision_csv(o, wp);
    else {
      draw_work_precision(o, wp,
                          fmt::format("{} — track {} \"{}\": plant integrators on this passage (k = {:g} N/m)", o.song,
                                      track, t.name, so.plant->params.string.stiffness));
    }
    return kExitOk;
  }
  if (dev.core().faults() != 0) {
    std::fprintf(stderr, "warning: the device latched faults 0x%x (see docs/spidar.md, Firmware drive)\n",
                 dev.core().faults());
  }
  // Notes the device could not play as scheduled: the passage sent more than its link and voices take.
  if (const protocol::Status st = dev.core().status(); st.late + st.rejected + st.stolen > 0) {
    std::fprintf(stderr,
                 "warning: of %zu notes the device started %u late, rejected %u and cut %u short for newer ones "
                 "(more notes at once than its link and %u voices take)\n",
                 notes.size(), st.late, st.rejected, st.stolen, static_cast<unsigned>(synth::kVoiceCount));
  }
  const simulate::Fidelity fid =
      simulate::measure_fidelity(samples, opts.tick_hz, static_cast<double>(settings.peak_force_n));
  std::fprintf(stderr,
               "fidelity: actual/commanded RMS over %zu windows of 20 ms: mean |error| %.1f%%, worst %.1f%%; "
               "delay %.2f ms\n",
               fid.windows, 100.0 * fid.mean_ratio_error, 100.0 * fid.worst_ratio_error,
               1e3 * fid.lag_ticks / opts.tick_hz);

  const double t0 = static_cast<double>(first) / opts.tick_hz;
  if (fmt_out == "csv") {
    write_csv(o, samples, t0, opts.tick_hz);
  } else {
    std::vector<float> commanded, actual;
    for (const simulate::ForceSample& s : samples) {
      commanded.push_back(s.commanded);
      actual.push_back(s.actual);
    }
    output::TracePlotSpec spec;
    spec.title = fmt::format("{} — track {} \"{}\" ({}) on the simulated device{}", o.song, track, t.name,
                             midi::gm_instrument_name(t.program(), t.channel()), o.plain_drive ? ", plain drive" : "");
    spec.rate_hz = opts.tick_hz;
    spec.t0_s = t0;
    output::write_traces_png(o.out,
                             {{"actual (string force on the grip)", actual, 0.90, 0.45, 0.15},
                              {"commanded (vibration × peak force)", commanded, 0.10, 0.25, 0.60}},
                             spec, o.force);
  }
  return kExitOk;
}

}  // namespace

void register_sim(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<SimCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sim", "Play one track on the simulated device and plant: commanded vs actual grip force (CSV or PNG)");
  cmd->add_option("SONG", o->song, "MIDI file")->required();
  cmd->add_option("--track", o->track, "Track index, or part of its name or instrument (see hmp info)")->required();
  cmd->add_option("--out", o->out,
                  "FILE.csv (t_s,commanded_n,actual_n,reported_n,min_tension_n,max_tension_n), FILE.png, '-' = CSV")
      ->capture_default_str();
  cmd->add_option("--from", o->from_s, "Start of the window in seconds of the song");
  cmd->add_option("--to", o->to_s, "End of the window in seconds of the song");
  cmd->add_option("--peak-force", o->peak_force_n,
                  "Force at full scale in N (device setting; default: the config's [device] peak_force_n, else 1)");
  cmd->add_flag("--plain-drive", o->plain_drive, "Stall duties without the dynamics compensation (to compare)");
  cmd->add_option("--integrator", o->plant.integrator,
                  "Plant integrator: " + simulate::integrator_names() + " (default " +
                      std::string(sim::plant::method_name(simulate::default_method())) + ", or [plant] integrator)");
  cmd->add_option("--string-stiffness", o->plant.string_stiffness,
                  "String stiffness in N/m (default 1e4, or [plant] string_stiffness)");
  cmd->add_option("--max-step", o->plant.max_step,
                  "Largest internal step of the integrator in s, at least 1e-7 (default: the integrator's own)");
  cmd->add_flag("--work-precision", o->work_precision,
                "Replay the passage under every integrator and CVODE: error against run time (table, --out "
                "FILE.csv or FILE.png); at most 20 s, pick it with --from/--to (about 15 s of computing a second "
                "of passage at the default strings, more at stiffer ones)");
  cmd->add_flag("-f,--force", o->force, "Overwrite an existing output file");
  add_haptic_options(cmd, o->haptic);
  cmd->callback([o, &registry] { registry.set([o] { return run_sim(*o); }); });
}

}  // namespace hmp::cli
