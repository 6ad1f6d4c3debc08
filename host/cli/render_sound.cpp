#include "host/cli/render_sound.hpp"

#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/offline_render.hpp"
#include "host/audio/soundfont.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/progress.hpp"
#include "host/common/song_window.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/output/output_file.hpp"

namespace hmp::cli {

namespace {
// The longest sound rendered at once: 6 h of 44.1 kHz stereo float samples are 7.6 GB.
constexpr double kLongestSoundS = 6 * 3600.0;
}  // namespace

void run_sound_render(const SoundRenderRequest& r) {
  if (output::extension_of(r.out) != "wav") throw BadInput("--sound: the output is a .wav file (--out FILE.wav)");
  check_window_times(r.from_s, r.to_s);  // before the output and the song, as every window
  output::check_writable(r.out, r.force);
  const midi::ReadResult read = midi::load_song(r.song);
  // The sound goes on for kSoundTailS after the song's last event (its notes' release); a window past
  // that holds nothing to hear: a --from there is refused, a --to there is that end.
  const std::int64_t sound_end_us = read.song.duration_us + saturated_us(kSoundTailS);
  SongWindowUs w;
  haptics::check_song_then_warn(read, warn_on_stderr, [&] {
    if (r.from_s && *r.from_s >= static_cast<double>(sound_end_us) * 1e-6) {
      throw BadInput(fmt::format("--from {}: the song's sound ends at {:.3f} s ({:g} s after its last event)",
                                 *r.from_s, static_cast<double>(sound_end_us) * 1e-6, kSoundTailS));
    }
    w = song_window(r.from_s, r.to_s, sound_end_us);
    const double span_s = static_cast<double>(w.end_us - w.begin_us) * 1e-6;
    if (span_s > kLongestSoundS) {
      throw BadInput(fmt::format("--from {} --to {}: longer than {:g} hours (render it in parts)",
                                 static_cast<double>(w.begin_us) * 1e-6, static_cast<double>(w.end_us) * 1e-6,
                                 kLongestSoundS / 3600));
    }
  });
  const double from = static_cast<double>(w.begin_us) * 1e-6, to = static_cast<double>(w.end_us) * 1e-6;

  audio::AudioOptions options;
  options.synth.sample_rate = 44100;
  if (r.soundfont) options.soundfont = *r.soundfont;
  // The sound is all this output holds: without a SoundFont it would be silence (play and the video go on
  // silent with a warning; this file would be nothing but that).
  if (!audio::find_soundfont(options.soundfont)) {
    throw std::runtime_error(
        "--sound: no General MIDI SoundFont found (install fluid-soundfont-gm, or name one with --soundfont)");
  }
  ProgressBar bar("rendering sound");
  const audio::RenderedAudio sound =
      audio::render_offline(audio::audio_events(read.song), w.begin_us, w.end_us, options, warn_on_stderr,
                            [&](std::uint64_t done, std::uint64_t total) { bar.update(done, total); });
  output::StagedOutput staged(r.out);  // written as OUT.part, renamed once whole
  audio::write_wav(staged.part(), sound);
  staged.commit();
  std::fprintf(stderr, "%s: %.2f s of the song's sound, 44.1 kHz stereo%s\n", r.out.c_str(), to - from,
               sound.silent_fallback ? " (silent: no SoundFont)" : "");
}

}  // namespace hmp::cli
