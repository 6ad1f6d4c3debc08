#include "host/cli/render_sound.hpp"

#include <cstdio>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/offline_render.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/progress.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/output/output_file.hpp"

namespace hmp::cli {

void run_sound_render(const SoundRenderRequest& r) {
  if (output::extension_of(r.out) != "wav") throw BadInput("--sound: the output is a .wav file (--out FILE.wav)");
  if (r.from_s && !(*r.from_s >= 0)) throw BadInput(fmt::format("--from {}: must be ≥ 0", *r.from_s));
  output::check_writable(r.out, r.force);
  const midi::ReadResult read = midi::load_song(r.song);
  for (const midi::Warning& w : read.warnings) warn_on_stderr(w.message);
  const double from = r.from_s.value_or(0.0);
  const double to = r.to_s.value_or(read.song.duration_s() + kSoundTailS);
  if (!(to > from)) throw BadInput(fmt::format("--from {} --to {}: the passage is empty", from, to));
  if (to - from > 6 * 3600.0) throw BadInput(fmt::format("--from {} --to {}: longer than 6 hours", from, to));

  audio::AudioOptions options;
  options.synth.sample_rate = 44100;
  if (r.soundfont) options.soundfont = *r.soundfont;
  ProgressBar bar("rendering sound");
  const audio::RenderedAudio sound = audio::render_offline(
      audio::audio_events(read.song), static_cast<std::int64_t>(from * 1e6), static_cast<std::int64_t>(to * 1e6),
      options, warn_on_stderr, [&](std::uint64_t done, std::uint64_t total) { bar.update(done, total); });
  output::StagedOutput staged(r.out);  // written as OUT.part, renamed once whole
  audio::write_wav(staged.part(), sound);
  staged.commit();
  std::fprintf(stderr, "%s: %.2f s of the song's sound, 44.1 kHz stereo%s\n", r.out.c_str(), to - from,
               sound.silent_fallback ? " (silent: no SoundFont)" : "");
}

}  // namespace hmp::cli
