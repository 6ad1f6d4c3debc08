#include "host/player/live_terminal.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>

#include <fmt/format.h>

#include "host/transport/handshake.hpp"

namespace hmp::player {

namespace {
std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig); }
}  // namespace

void install_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

int stop_signal() { return g_stop_signal.load(); }

Command command_for(Key k) {
  switch (k) {
    case Key::space: return Command::toggle_pause;
    case Key::left: return Command::seek_back;
    case Key::right: return Command::seek_forward;
    case Key::next_track: return Command::next_track;
    case Key::previous_track: return Command::previous_track;
    case Key::envelope: return Command::cycle_envelope;
    case Key::mapping: return Command::cycle_mapping;
    case Key::slower: return Command::slower;
    case Key::faster: return Command::faster;
    case Key::next_song: return Command::next_song;
    case Key::previous_song: return Command::previous_song;
    case Key::quit: return Command::quit;
  }
  return Command::quit;
}

std::optional<char> KeyDecoder::feed(unsigned char byte) {
  switch (state_) {
    case State::escape:
      state_ = byte == '[' ? State::csi : byte == 'O' ? State::ss3 : byte == 0x1B ? State::escape : State::text;
      return std::nullopt;  // ESC and a key: Alt held, as Alt+key in the window, nothing
    case State::ss3:
      state_ = State::text;
      return byte == 'C' ? std::optional<char>('>') : byte == 'D' ? std::optional<char>('<') : std::nullopt;
    case State::csi:
    case State::csi_params: {
      if (byte >= 0x20 && byte <= 0x3F) {  // parameters and intermediates: a modified or other key
        state_ = State::csi_params;
        return std::nullopt;
      }
      const bool plain = state_ == State::csi;  // the final byte: an arrow only without parameters
      state_ = State::text;
      if (plain && byte == 'C') return '>';
      if (plain && byte == 'D') return '<';
      return std::nullopt;
    }
    case State::text: break;
  }
  if (byte == 0x1B) {
    state_ = State::escape;
    return std::nullopt;
  }
  if (byte == '\r' || byte == '\n') return '\n';
  if (byte < 0x20 || byte >= 0x7F) return std::nullopt;  // other control bytes; UTF-8 has no key here
  return static_cast<char>(byte);
}

std::optional<char> KeyDecoder::idle() {
  if (state_ != State::escape) return std::nullopt;
  state_ = State::text;
  return 'q';
}

std::optional<Key> key_for_char(char c) {
  switch (c) {
    case ' ': return Key::space;
    case '<': return Key::left;
    case '>': return Key::right;
    case 't': return Key::next_track;
    case 'T': return Key::previous_track;
    case 'e': return Key::envelope;
    case 'm': return Key::mapping;
    case '[': return Key::slower;
    case ']': return Key::faster;
    case 'n': return Key::next_song;
    case 'p': return Key::previous_song;
    case 'q': return Key::quit;
    default: return std::nullopt;
  }
}

RawKeys::RawKeys() {
  if (!isatty(STDIN_FILENO) || tcgetattr(STDIN_FILENO, &saved_) != 0) return;
  termios raw = saved_;
  raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);  // ISIG stays: Ctrl-C is still SIGINT
  raw.c_cc[VMIN] = 0;
  raw.c_cc[VTIME] = 0;
  active_ = tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
}

RawKeys::~RawKeys() { restore(); }

void RawKeys::restore() {
  if (active_) tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
  active_ = false;
}

std::optional<Key> RawKeys::poll() {
  while (const std::optional<char> c = next_char()) {
    if (const std::optional<Key> key = key_for_char(*c)) return key;
  }
  return std::nullopt;
}

std::optional<char> RawKeys::next_char() {
  if (!active_) return std::nullopt;
  unsigned char byte = 0;
  while (read(STDIN_FILENO, &byte, 1) == 1) {
    if (const std::optional<char> c = decoder_.feed(byte)) return c;
  }
  return decoder_.idle();
}

const char* state_word(const Snapshot& s) {
  if (s.device_lost) return "DEVICE LOST";
  return s.paused ? "paused " : "playing";
}

std::string format_status(const Snapshot& s) {
  // Most important first: a narrow terminal cuts the end (envelope and mapping).
  const Counters& c = s.counters;
  return fmt::format("{}{} {}/{}{}  track {} \"{}\"  sent {} played {}  queue {}/{}  late {} stolen {}  env {} map {}",
                     s.song_label.empty() ? "" : s.song_label + "  ", state_word(s), format_time(s.song_us),
                     format_time(s.end_us), s.speed != 1.0 ? fmt::format(" ×{:g}", s.speed) : "", s.track, s.track_name,
                     c.notes_sent, c.notes_played, s.queue_capacity - s.queue_free, s.queue_capacity, c.late, c.stolen,
                     s.envelope, s.mapping);
}

void StatusLine::draw() {
  winsize ws{};
  std::size_t width = 80;
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 1) width = ws.ws_col;
  std::string shown = line_.size() >= width ? line_.substr(0, width - 1) : line_;
  std::fprintf(stderr, "\r\x1b[K%s", shown.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void StatusLine::show(const Snapshot& s, bool force) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  line_ = format_status(s);
  draw();
}

void StatusLine::message(const std::string& text) {
  if (enabled_ && drawn_) std::fprintf(stderr, "\r\x1b[K");
  std::fprintf(stderr, "%s\n", text.c_str());
  if (enabled_ && drawn_) draw();
  std::fflush(stderr);
}

void StatusLine::close() {
  if (enabled_ && drawn_) std::fprintf(stderr, "\n");
  drawn_ = false;
  std::fflush(stderr);
}

}  // namespace hmp::player
