#pragma once
// The terminal side of `hmp play` (design §3, §14): live keys in raw mode and a one-line status that
// redraws itself. Only on a terminal: without one, nothing here touches stdin or prints a status.
//
// Raw mode keeps ISIG, so Ctrl-C still raises SIGINT (the player stops cleanly on it); the previous
// terminal settings come back when the RawKeys object goes away, also when an exception unwinds.
#include <chrono>
#include <optional>
#include <string>

#include "host/common/time_format.hpp"

#include <termios.h>

#include "host/player/player.hpp"

namespace hmp::player {

enum class Key {
  space,
  left,
  right,
  next_track,
  previous_track,
  envelope,
  mapping,
  slower,
  faster,
  next_song,
  previous_song,
  quit
};

// The command a key stands for (design §14 keys: pause, seek, switch track/envelope/mapping, quit).
Command command_for(Key k);

// A printable key's meaning (the window's keys too; '<' and '>' stand for the arrows there).
std::optional<Key> key_for_char(char c);

// Decodes a terminal's key bytes into the characters the window's keys give (host/view/gl/gl_window.cpp),
// so that both read one alphabet (key_for_char, the study's keys): a printable byte as itself, Enter as
// '\n', the arrows ← → (ESC [ D / C, ESC O D / C in application mode) as '<' '>'. Other escape
// sequences (↑ ↓, function keys, Ctrl+arrows: ESC [ parameters final) and Alt+key (ESC, key) give
// nothing, as such keys do in the window; Esc pressed alone — an ESC with no byte after it in the same
// read, idle() — gives 'q', as Esc in the window. Feed bytes one at a time.
class KeyDecoder {
 public:
  std::optional<char> feed(unsigned char byte);
  std::optional<char> idle();  // no byte waiting now: a lone ESC is the Esc key

 private:
  enum class State { text, escape, csi, csi_params, ss3 } state_ = State::text;
};

class RawKeys {
 public:
  RawKeys();  // raw mode when stdin is a terminal, otherwise inactive
  ~RawKeys();
  RawKeys(const RawKeys&) = delete;
  RawKeys& operator=(const RawKeys&) = delete;
  bool active() const { return active_; }
  std::optional<Key> poll();        // the next key with a meaning in key_for_char; never blocks
  std::optional<char> next_char();  // the next decoded character (hmp study's keys); never blocks
  void restore();

 private:
  bool active_ = false;
  termios saved_{};
  KeyDecoder decoder_;
};

// The status line on stderr: redrawn at most 10 times a second, cut to the terminal's width so that it
// never wraps. Messages printed through it go above the line.
class StatusLine {
 public:
  explicit StatusLine(bool enabled) : enabled_(enabled) {}
  bool enabled() const { return enabled_; }
  void show(const Snapshot& s, bool force = false);
  void message(const std::string& text);  // a line of its own (works without a terminal too)
  void close();                           // ends the line (the last status stays visible)

 private:
  void draw();
  bool enabled_;
  bool drawn_ = false;
  std::string line_;
  std::chrono::steady_clock::time_point last_{};
};

std::string format_status(const Snapshot& s);
const char* state_word(const Snapshot& s);  // "playing", "paused " or "DEVICE LOST"

// SIGINT, SIGTERM and SIGHUP set a flag instead of killing the process; the player polls it.
void install_stop_signals();
int stop_signal();  // 0, or the signal that arrived

}  // namespace hmp::player
