// hmp live [--list] [--input PORT] [--api alsa|jack] [--channel N] [--instrument GM] [--key-range LOW:HIGH]
// [--envelope NAME] [--mapping MODE] [--device SPEC] [--no-audio …] [--sync-sound | --vibration-delay-ms MS]
// [--seconds S] [--wait] — feel MIDI as it is played: every note of a keyboard or a DAW, from an ALSA
// sequencer or JACK input port, sent to the device the moment it arrives (or when its sound is heard) and
// heard through FluidSynth (docs/live.md).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "host/cli/commands.hpp"
#include "host/cli/device_hello.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/percentile.hpp"
#include "host/output/output_file.hpp"
#include "host/audio/audio_player.hpp"
#include "host/live/live_session.hpp"
#include "host/live/live_sound.hpp"
#include "host/midi/gm.hpp"
#include "host/live/midi_port.hpp"
#include "host/player/live_terminal.hpp"
#include "host/view/live_view.hpp"

namespace hmp::cli {
namespace {

struct LiveOptions {
  bool list = false;
  std::string input;  // empty: a port of our own named "hmp"
  std::optional<std::string> api;
  std::optional<int> channel;             // 1–16; none: every channel
  std::optional<std::string> key_range;   // default: the instrument's range, else the piano's
  std::optional<std::string> instrument;  // a GM program: the sound, and the envelope unless --envelope
  std::optional<std::string> envelope;    // default: the instrument's `auto` preset (the piano's: harpsichord)
  AudioCliOptions audio;
  std::string mapping = "paper";
  std::string device = "auto";
  double seconds = 0;
  bool wait = false;
  bool no_view = false;
  std::optional<std::string> log;
  bool force = false;
  bool sync_sound = false;                   // the vibration waits for the sound's output latency
  std::optional<double> vibration_delay_ms;  // or for this long
};

// The longest a vibration may be held back: far beyond any sound path worth matching.
constexpr double kMaxVibrationDelayMs = 1000;

void check_vibration_delay(const LiveOptions& o) {
  if (o.vibration_delay_ms) {
    const double ms = *o.vibration_delay_ms;
    if (!(ms >= 0 && ms <= kMaxVibrationDelayMs))
      throw BadInput(fmt::format("--vibration-delay-ms {}: a delay from 0 to {:g} ms", ms, kMaxVibrationDelayMs));
  }
  if (o.sync_sound && o.audio.no_audio)
    throw BadInput("--sync-sound with --no-audio: there is no sound to wait for (--vibration-delay-ms sets a delay)");
}

live::MidiApi parse_api(const std::string& text) {
  if (text == "alsa") return live::MidiApi::alsa;
  if (text == "jack") return live::MidiApi::jack;
  throw BadInput("--api " + text + ": use alsa or jack");
}

const live::MidiPortBackend& backend() {
  std::string why;
  const live::MidiPortBackend* b = live::midi_port_backend(&why);
  if (b == nullptr) throw std::runtime_error("MIDI input is not available: " + why);
  return *b;
}

int list_ports() {
  const live::MidiPortBackend& b = backend();
  for (const live::MidiApi api : {live::MidiApi::alsa, live::MidiApi::jack}) {
    std::string error;
    const std::vector<live::MidiPortInfo> ins = b.inputs(api, error);
    if (!error.empty()) {
      fmt::print("{}: not available: {}\n", live::name(api), error);
      continue;
    }
    const std::vector<live::MidiPortInfo> outs = b.outputs(api, error);
    for (const auto& [ports, what] : {std::pair{&ins, "input"}, std::pair{&outs, "output (hmp play --midi-out)"}}) {
      fmt::print("{}: {} {} port{}\n", live::name(api), ports->size(), what, ports->size() == 1 ? "" : "s");
      for (const live::MidiPortInfo& p : *ports) fmt::print("  {}\n", p.name);
    }
  }
  return kExitOk;
}

// --api as given, else live::default_api.
live::MidiApi choose_api(const LiveOptions& o, const live::MidiPortBackend& b) {
  return o.api ? parse_api(*o.api) : live::default_api(b);
}

// --instrument as a GM program 0–127; nullopt when not given.
std::optional<std::uint8_t> instrument(const LiveOptions& o) {
  if (!o.instrument) return std::nullopt;
  const std::optional<std::uint8_t> program = midi::find_gm_program(*o.instrument);
  if (!program)
    throw BadInput("--instrument " + *o.instrument + ": not a GM program (1–128, or a name as hmp info shows)");
  return program;
}

// `program`: --instrument, parsed once by the caller.
live::MapperOptions mapper_options(const LiveOptions& o, std::optional<std::uint8_t> program) {
  live::MapperOptions m;
  if (o.channel && (*o.channel < 1 || *o.channel > 16))
    throw BadInput(fmt::format("--channel {}: use 1–16 (without --channel: every channel)", *o.channel));
  m.channel = o.channel ? *o.channel - 1 : -1;
  if (o.key_range) {
    m.keys = live::parse_key_range(*o.key_range);
  } else if (program) {
    const midi::KeySpan span = midi::gm_key_range(*program);
    m.keys = {span.low, span.high};
  }
  envelope::Preset preset = envelope::auto_preset(program.value_or(0), 0);
  if (o.envelope && !envelope::find_builtin(o.envelope->c_str(), preset))
    throw BadInput("--envelope " + *o.envelope + ": unknown");
  m.preset = static_cast<std::uint8_t>(preset);
  m.mode = parse_mapping_mode(o.mapping);
  if (!(o.seconds >= 0)) throw BadInput(fmt::format("--seconds {}: must be ≥ 0", o.seconds));
  return m;
}

using SteadyClock = std::chrono::steady_clock;

// Whether --seconds have gone by since `started` (the command's start: waiting for a port counts).
bool time_up(const LiveOptions& o, SteadyClock::time_point started) {
  return o.seconds > 0 && std::chrono::duration<double>(SteadyClock::now() - started).count() >= o.seconds;
}

// The port, opened; with --wait, tried again every half second until it is there (or a stop signal, or
// the end of --seconds: nullptr).
std::unique_ptr<live::MidiInput> open_port(const live::MidiPortBackend& b, live::MidiApi api, const LiveOptions& o,
                                           live::LiveSession& session, bool first, SteadyClock::time_point started) {
  bool said = false;
  for (;;) {
    std::string error;
    std::unique_ptr<live::MidiInput> in = b.open(api, o.input, &live::LiveSession::receive, &session, error);
    if (in) return in;
    if (o.wait && time_up(o, started)) return nullptr;
    // A port that is not there, or no server to ask, is the user's to fix: bad input, unless we wait.
    if (!o.wait || player::stop_signal() != 0) {
      if (first) throw BadInput(fmt::format("{} MIDI input: {}", live::name(api), error));
      return nullptr;
    }
    if (!said)
      std::fprintf(stderr, "%s MIDI input: %s; waiting for it (Ctrl-C stops)\n", live::name(api), error.c_str());
    said = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
}

std::string latency_text(const live::LiveProgress& p, double delay_ms) {
  if (p.latency_ms.empty()) return "no latency measured";
  return fmt::format("message to Started report p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms over {} notes{}",
                     percentile(p.latency_ms, 50), percentile(p.latency_ms, 99), percentile(p.latency_ms, 100),
                     p.latency_ms.size(),
                     delay_ms > 0 ? fmt::format(", {:.1f} ms of it the vibration delay", delay_ms) : "");
}

// One JSON line per note-on (times in µs of CLOCK_MONOTONIC, which JACK's clock reads too; started_us
// null when no Started report came), then a summary line. Checked before the run; written at its end.
void write_log(const std::string& path, const live::LiveSession& session) {
  output::FilePtr f = output::open_for_writing(path, true);
  for (const live::NoteRecord& n : session.notes()) {
    nlohmann::json line = {{"channel", n.channel + 1},
                           {"key", n.key},
                           {"received_us", n.received_us},
                           {"sent_us", n.sent_us},
                           {"started_us", nullptr}};
    if (n.started_us != 0) {
      line["started_us"] = n.started_us;
      line["actual_tick"] = n.actual_tick;
    }
    std::fprintf(f.get(), "%s\n", line.dump().c_str());
  }
  const live::LiveProgress& p = session.progress();
  const nlohmann::json summary = {{"summary",
                                   {{"notes_on", p.counts.notes_on},
                                    {"notes_off", p.counts.notes_off},
                                    {"bends", p.counts.bends},
                                    {"started", p.started},
                                    {"refused", p.refused},
                                    {"dropped", p.dropped},
                                    {"vibration_delay_ms", session.vibration_delay_ms()}}}};
  std::fprintf(f.get(), "%s\n", summary.dump().c_str());
  output::close_output(f);
}

// The window: the notes at the present line as they are played, scrolling into the past, over the keys
// of the mapping's range; `q` in it (or closing it) stops the run. Null and `error` when none can be had.
std::unique_ptr<view::LiveView> open_live_view(const midi::Song& channels, live::LiveSession& session,
                                               const live::MapperOptions& mo, const std::string& overlay,
                                               std::atomic<bool>& quit, std::string& error) {
  view::LiveViewOptions options;
  options.setup.title = "hmp live";
  options.help = {"play notes on the MIDI input: each is felt and drawn as it comes", "q / Esc  quit"};
  options.setup.keys = std::pair{mo.keys.low, mo.keys.high};
  view::LiveViewHooks hooks;
  hooks.song_time = [&session](view::Clock::time_point t) {
    return session.session_us() + std::chrono::duration_cast<std::chrono::microseconds>(t - view::Clock::now()).count();
  };
  const auto haptic = static_cast<std::uint32_t>(std::max(mo.channel, 0));
  hooks.state = [overlay, haptic] {
    view::LiveState st;
    st.haptic_track = haptic;
    st.overlay = overlay;
    return st;
  };
  hooks.key = [&quit](char k) {
    if (k == 'q') quit = true;
  };
  hooks.played = [&session, notes = std::vector<live::PlayedNote>()](std::int64_t t0, std::int64_t t1,
                                                                     std::vector<view::Bar>& out) mutable {
    notes.clear();
    session.played(t0, t1, notes);
    for (const live::PlayedNote& n : notes) out.push_back({n.start_us, n.end_us, n.key, n.velocity, n.channel});
  };
  return view::LiveView::open(channels, std::move(options), std::move(hooks), error);
}

int run_live(const LiveOptions& o) {
  const SteadyClock::time_point started = SteadyClock::now();
  if (o.list) return list_ports();
  const std::optional<std::uint8_t> program = instrument(o);
  const live::MapperOptions mo = mapper_options(o, program);
  const audio::AudioOptions audio_opts = audio_options(o.audio);  // checks --soundfont
  if (o.log) output::check_writable(*o.log, o.force);
  if (o.api) parse_api(*o.api);  // bad input before any port or device is opened
  const transport::DeviceSpec device = transport::parse_device_spec(o.device);
  check_vibration_delay(o);
  const live::MidiPortBackend& b = backend();
  const live::MidiApi api = choose_api(o, b);
  if (std::string error; !o.wait) {
    // Nothing to listen to: said before the device is opened.
    const std::vector<live::MidiPortInfo> ports = b.inputs(api, error);
    if (!error.empty()) throw BadInput(fmt::format("{} MIDI input: {}", live::name(api), error));
    const bool named = o.input.empty() || std::any_of(ports.begin(), ports.end(), [&](const live::MidiPortInfo& p) {
                         return live::named_like(p.name, o.input);
                       });
    if (!named) throw BadInput(live::no_port_named(api, true, o.input));
  }

  transport::OpenedDevice opened = transport::open_device(device);
  if (!opened.note.empty()) std::fprintf(stderr, "%s\n", opened.note.c_str());
  player::DeviceLink link(*opened.transport, link_options_for(opened));
  connect_and_describe(link, opened);
  if (opened.spec.kind == transport::DeviceSpec::Kind::qemu && !opened.spec.qemu_net) {
    // The emulated UART takes ~90 µs a byte: a Live report ~1.7 ms before the device sees it.
    std::fprintf(stderr, "live: the QEMU board's UART adds ~2 ms a note; qemu:net is its fast link\n");
  }
  live::LiveSession session(link, mo, o.log.has_value());
  audio::AudioPlayer sound(audio_opts);
  live::LiveSound heard(mo.channel, program);
  if (sound.audible()) {
    sound.set_events({});
    sound.start(0);
    await_audio_period(sound);
  }
  double delay_ms = o.vibration_delay_ms.value_or(0.0);
  if (o.sync_sound) {
    if (sound.audible())
      delay_ms = sound.output_latency_s() * 1e3;
    else
      std::fprintf(stderr, "warning: --sync-sound: no sound device, so no sound to wait for; felt at once\n");
  }
  session.set_vibration_delay_us(std::llround(delay_ms * 1e3));
  if (sound.audible()) {
    std::fprintf(
        stderr, "audio: %s, output latency %.1f ms%s\n", sound.driver_name().c_str(), sound.output_latency_s() * 1e3,
        o.sync_sound                       ? " (the vibration waits as long: --sync-sound)"
        : session.vibration_delay_ms() > 0 ? ""
                                           : " (the vibration comes that much before the sound; --sync-sound waits)");
    session.set_listener([&](const live::ChannelMessage& msg) {
      if (const std::optional<audio::AudioEvent> e = heard.on_message(msg)) sound.play_now(*e);
    });
  }
  player::install_stop_signals();
  std::unique_ptr<live::MidiInput> in = open_port(b, api, o, session, true, started);
  if (!in) {
    std::fprintf(stderr, "live: no MIDI input came within --seconds %g\n", o.seconds);
    session.finish();
    if (o.log) write_log(*o.log, session);  // its summary: nothing came
    return kExitOk;
  }
  std::fprintf(
      stderr, "live: input %s, %s, %s, keys %s, envelope %s, mapping %s; q or Ctrl-C stops\n", in->name().c_str(),
      o.channel ? fmt::format("channel {}", *o.channel).c_str() : "every channel",
      program ? midi::gm_program_name(*program) : "the input's programs",
      (live::to_string(mo.keys) + (o.key_range ? ""
                                   : program   ? fmt::format(" (the {}'s range)", midi::gm_program_name(*program))
                                               : std::string(" (the piano's)")))
          .c_str(),
      envelope::name(static_cast<envelope::Preset>(mo.preset)), o.mapping.c_str());
  const bool tty = isatty(STDERR_FILENO) != 0;
  const auto show = [&](const live::LiveProgress& p) {
    if (!tty) return;
    const std::string held = p.held == 0 ? "" : fmt::format(", {} events waiting for the device", p.held);
    const std::string lost = p.dropped == 0 ? "" : fmt::format(", {} MIDI messages lost", p.dropped);
    std::fprintf(stderr, "\r\033[Knotes %llu, device started %llu%s%s%s",
                 static_cast<unsigned long long>(p.counts.notes_on), static_cast<unsigned long long>(p.started),
                 held.c_str(), lost.c_str(), p.last_error.empty() ? "" : (", refused: " + p.last_error).c_str());
  };
  // The window's roll has a layer per MIDI channel; the song behind it has no notes.
  midi::Song channels;
  channels.tracks.resize(16);
  std::atomic<bool> quit{false};
  std::unique_ptr<view::LiveView> window;
  if (!o.no_view) {
    std::string why;
    window = open_live_view(
        channels, session, mo,
        fmt::format("live   {}   keys {}   envelope {}   mapping {}   (q: quit)", in->name(), live::to_string(mo.keys),
                    envelope::name(static_cast<envelope::Preset>(mo.preset)), o.mapping),
        quit, why);
    if (!window)
      std::fprintf(stderr, "warning: no animation window: %s; going on without it (--no-view: do not try)\n",
                   why.c_str());
  }
  player::RawKeys keys;  // q or Esc in the terminal quits, as in the window
  const auto stop = [&] {
    while (const std::optional<char> c = keys.next_char()) {
      if (*c == 'q') quit = true;
    }
    return player::stop_signal() != 0 || quit.load() || (window && window->closed());
  };
  int code = kExitOk;
  for (;;) {
    const double elapsed = std::chrono::duration<double>(SteadyClock::now() - started).count();
    const double left = o.seconds > 0 ? std::max(1e-3, o.seconds - elapsed) : 0;
    const live::LiveEnd end = session.run(*in, left, stop, show);
    if (end != live::LiveEnd::port_gone) break;
    if (tty) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "live: the MIDI input %s is gone%s\n", in->name().c_str(),
                 o.wait ? "; waiting for it to come back" : "");
    in.reset();
    if (!o.wait || !(in = open_port(b, api, o, session, false, started))) {
      code = o.wait ? kExitOk : kExitFailure;
      break;
    }
  }
  window.reset();
  keys.restore();
  session.finish();
  if (tty) std::fprintf(stderr, "\n");
  const live::LiveProgress& p = session.progress();
  fmt::print(
      "live: {} notes on, {} off, {} bends; the device started {} ({}); {} report(s) refused; at most {} "
      "events waited for the device\n",
      p.counts.notes_on, p.counts.notes_off, p.counts.bends, p.started, latency_text(p, session.vibration_delay_ms()),
      p.refused, p.most_held);
  if (!p.last_error.empty()) std::fprintf(stderr, "live: the device refused %s\n", p.last_error.c_str());
  if (p.dropped > 0) {
    std::fprintf(stderr, "live: %llu MIDI message(s) lost: hmp fell behind its input\n",
                 static_cast<unsigned long long>(p.dropped));
  }
  if (o.log) write_log(*o.log, session);
  return code;
}

}  // namespace

void register_live(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<LiveOptions>();
  CLI::App* cmd = app.add_subcommand("live", "Feel MIDI as it is played: a keyboard's or a DAW's notes, at once");
  cmd->add_flag("--list", o->list,
                "List the MIDI input ports (and the output ports hmp play can send a song to) and exit");
  cmd->add_option("--input", o->input,
                  "The input port whose name contains PORT (default: a port of our own named hmp, to connect to)");
  cmd->add_option("--api", o->api, "alsa or jack (default: jack where a JACK server runs, else alsa)");
  cmd->add_option("--channel", o->channel, "Only this MIDI channel, 1–16 (default: every channel)");
  cmd->add_option("--key-range", o->key_range,
                  "The keys the pitch mapping spreads over, LOW:HIGH as numbers or names (default: the "
                  "--instrument's range, else the piano's 21:108, A0–C8)");
  cmd->add_option("--instrument", o->instrument,
                  "The sound: a GM program, 1–128 or its name (default: the input's program changes, piano "
                  "until one comes); also the envelope, unless --envelope");
  cmd->add_option("--envelope", o->envelope,
                  "A built-in envelope preset (default: the instrument's, as `auto` picks it; harpsichord for "
                  "the piano)");
  add_audio_options(cmd, o->audio);
  cmd->add_option("--mapping", o->mapping, "Pitch mapping: paper (default), rank, constant, legacy2013");
  cmd->add_option("--device", o->device, kDeviceHelp);
  cmd->add_option("--seconds", o->seconds,
                  "Stop after this many seconds, waiting for the port (--wait) included (default: at Ctrl-C)");
  cmd->add_flag("--wait", o->wait, "A port that is not there (yet, or any more) is waited for");
  cmd->add_flag("--no-view", o->no_view, "No window (by default the notes scroll by in one as they are played)");
  cmd->add_option("--log", o->log,
                  "JSON lines: every note-on with its times (received, sent, started), then a summary");
  cmd->add_flag("-f,--force", o->force, "Overwrite an existing log file");
  CLI::Option* sync = cmd->add_flag("--sync-sound", o->sync_sound,
                                    "Hold each vibration back by the sound's output latency, so that a note is felt "
                                    "when it is heard (default: felt at once, that much before)");
  cmd->add_option("--vibration-delay-ms", o->vibration_delay_ms,
                  "Hold each vibration back this long, 0–1000 ms (e.g. to meet another synthesizer's sound)")
      ->excludes(sync);
  cmd->callback([o, &registry] { registry.set([o] { return run_live(*o); }); });
}

}  // namespace hmp::cli
