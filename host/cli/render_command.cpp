// hmp render SONG --track T [--out FILE.csv|.wav|.png] — the haptic signal of one track at the device
// tick rate, computed by the same shared engine the firmware runs (design §3).
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "host/cli/commands.hpp"
#include "host/cli/render_sound.hpp"
#include "host/cli/render_video.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/common/progress.hpp"
#include "host/export/haptic_export.hpp"
#include "host/midi/gm.hpp"
#include "host/output/output_file.hpp"
#include "host/export/signal_export.hpp"

namespace hmp::cli {

namespace {

struct RenderOptions {
  std::string song;
  std::string track;
  std::string out = "-";
  std::optional<double> from_s, to_s;
  bool audible = false;
  bool sound = false;
  bool force = false;
  HapticCliOptions haptic;
  VideoCliOptions video;
};

int run_render(const RenderOptions& o) {
  if (o.video.soundfont) check_soundfont_option(*o.video.soundfont);  // before any work, as --out's check
  if (o.sound) {  // the song's own sound, all tracks: no haptic track involved
    if (o.audible) throw BadInput("--sound and --audible: one or the other (--audible is a track's haptic signal)");
    run_sound_render({o.song, o.out, o.from_s, o.to_s, o.video.soundfont, o.force});
    return kExitOk;
  }
  if (o.track.empty()) throw BadInput("--track: which track to render (see hmp info), or --sound for the song's sound");
  if (!exporting::is_signal_export(o.out) && !exporting::is_haptic_export(o.out) && !is_video_export(o.out)) {
    throw BadInput("--out " + o.out + ": use a .csv, .wav, .png, .ahap, .haptic or .mp4 file ('-': CSV on stdout)");
  }
  const exporting::SignalExport out{o.out, o.audible, o.force};
  const haptics::HapticOptions opts = resolve(o.haptic);
  const bool haptic_file = exporting::is_haptic_export(o.out);  // .ahap / .haptic (host/export/)
  if (is_video_export(o.out)) {                                 // .mp4 (host/video/)
    if (o.audible) throw BadInput("--audible: only with --out FILE.wav (a video takes --haptic-audio)");
    check_video_options(o.video);
    output::check_writable(o.out, o.force);
    const TrackWindow w = load_track_window(o.song, o.track, opts, o.from_s, o.to_s, warn_on_stderr);
    run_video_export(o.song, w, opts, o.video, o.out, o.force);
    return kExitOk;
  }
  if (haptic_file) {
    if (o.audible) throw BadInput("--audible: only with --out FILE.wav");
    output::check_writable(o.out, o.force);
  } else {
    exporting::check_export(out);  // fail before the work, not after
  }
  const TrackWindow w = load_track_window(o.song, o.track, opts, o.from_s, o.to_s, warn_on_stderr);
  const midi::ReadResult& r = w.read;
  const std::uint32_t track = w.track;
  const haptics::HapticTrack& ht = w.haptic;
  const std::uint64_t first = w.first_tick, end = w.end_tick;
  if (end - first > (std::uint64_t{1} << 31)) throw BadInput("--from/--to: window too long to render (> 2^31 ticks)");

  if (haptic_file) {
    const midi::Track& t = r.song.tracks[track];
    exporting::ExportSpec spec;
    spec.track = &ht;
    spec.opts = &opts;
    spec.first_tick = first;
    spec.end_tick = end;
    spec.title = fmt::format("track {} \"{}\", mapping {}, envelope {}", track, t.name, mapping::name(opts.mapping),
                             opts.envelope);
    spec.song = o.song;
    exporting::write_haptic_export(o.out, o.force, spec);
    return kExitOk;
  }

  const haptics::RenderSettings settings = haptics::render_settings(opts);
  ProgressBar bar("rendering");
  const auto notes = ht.device_notes();
  const std::vector<float> samples = haptics::render_signal(
      notes, ht.uploads, settings, first, end, [&](std::uint64_t d, std::uint64_t t) { bar.update(d, t); });

  std::vector<output::PlotNote> plot_notes;
  for (const haptics::HapticNote& n : ht.notes) plot_notes.push_back({n.start_s, n.end_s, n.key});
  const midi::Track& t = r.song.tracks[track];
  output::PlotSpec spec;
  spec.title =
      fmt::format("{} — track {} \"{}\" ({}), mapping {}, envelope {}", o.song, track, t.name,
                  midi::gm_instrument_name(t.program(), t.channel()), mapping::name(opts.mapping), opts.envelope);
  spec.tick_hz = opts.tick_hz;
  spec.first_tick = first;
  exporting::export_signal(out, samples, plot_notes, spec);
  return kExitOk;
}

}  // namespace

void register_render(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render",
                                     "Render one track's haptic signal (CSV, WAV, PNG plot, AHAP, .haptic), the song's "
                                     "sound (--sound) or the animation as MP4 video");
  cmd->add_option("SONG", o->song, "MIDI file")->required();
  CLI::Option* track = cmd->add_option(
      "--track", o->track, "Track index, or part of its name or instrument (see hmp info); not with --sound");
  cmd->add_option("--out", o->out,
                  "Output: FILE.csv (t_s,value), FILE.wav (float, tick rate), FILE.png, FILE.ahap, FILE.haptic, "
                  "FILE.mp4 (the animation with sound), '-' = CSV to stdout")
      ->capture_default_str();
  cmd->add_option("--from", o->from_s, "Start of the window in seconds of the song");
  cmd->add_option("--to", o->to_s, "End of the window in seconds of the song");
  cmd->add_flag("--audible", o->audible, "WAV resampled to 44.1 kHz so you can listen to it");
  cmd->add_flag("--sound", o->sound,
                "The song's own sound instead (all tracks, controllers; FluidSynth, 44.1 kHz stereo WAV)")
      ->excludes(track);
  cmd->add_flag("-f,--force", o->force, "Overwrite an existing output file");
  add_haptic_options(cmd, o->haptic);
  const std::vector<const CLI::Option*> video_only = add_video_options(cmd, o->video);
  cmd->callback([o, video_only, &registry] {
    registry.set([o, video_only] {
      // A video's settings with another output would be silently ignored.
      if (!is_video_export(o->out))
        for (const CLI::Option* option : video_only)
          if (option->count() > 0) throw BadInput(option->get_name() + ": only with --out FILE.mp4");
      return run_render(*o);
    });
  });
}

}  // namespace hmp::cli
