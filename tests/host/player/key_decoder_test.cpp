// A terminal's key bytes decoded into the characters the window's keys give (host/player/live_terminal.hpp):
// the arrows are '<' '>', no other escape sequence leaks its letters (↑ is ESC [ A: not the study's rank
// A), Alt+key gives nothing, and Esc pressed alone is 'q' without eating the key after it.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "host/player/live_terminal.hpp"

namespace {

using hmp::player::Key;
using hmp::player::key_for_char;
using hmp::player::KeyDecoder;

// Every character `bytes` gives, fed at once (as one read), then the decoder told that nothing follows.
std::string decode(const std::string& bytes) {
  KeyDecoder d;
  std::string out;
  for (const char b : bytes) {
    if (const std::optional<char> c = d.feed(static_cast<unsigned char>(b))) out += *c;
  }
  if (const std::optional<char> c = d.idle()) out += *c;
  return out;
}

TEST(KeyDecoder, PrintableKeysAndEnterAsThemselves) {
  EXPECT_EQ(decode(" tTemn[]pq0129abcABCu"), " tTemn[]pq0129abcABCu");
  EXPECT_EQ(decode("\r"), "\n");
  EXPECT_EQ(decode("\n"), "\n");
  EXPECT_EQ(decode(std::string("\x01\x7F\x08\0", 4)), "");  // control bytes: no key
  EXPECT_EQ(decode("\xC3\xA9"), "");                        // é: no key here
}

TEST(KeyDecoder, ArrowsAreTheWindowsLessAndGreater) {
  EXPECT_EQ(decode("\x1B[C\x1B[D"), "><");
  EXPECT_EQ(decode("\x1BOC\x1BOD"), "><");  // application cursor mode
  EXPECT_EQ(key_for_char('>'), Key::right);
  EXPECT_EQ(key_for_char('<'), Key::left);
}

TEST(KeyDecoder, OtherSequencesGiveNothingNotTheirLetters) {
  EXPECT_EQ(decode("\x1B[A\x1B[B"), "");  // ↑ ↓: not ranks A and B
  EXPECT_EQ(decode("\x1BOA\x1BOB"), "");
  EXPECT_EQ(decode("\x1B[1;5C\x1B[1;5D"), "");     // Ctrl+→ Ctrl+←: not a seek, not 'C'
  EXPECT_EQ(decode("\x1B[2~\x1B[15~\x1BOP"), "");  // Insert, F5, F1
  EXPECT_EQ(decode("\x1B[Aa\x1B[1;2Bb"), "ab");    // the keys after them still count
}

TEST(KeyDecoder, AltAndAKeyGiveNothing) {
  EXPECT_EQ(decode("\x1B"
                   "c"),
            "");  // Alt+c, as Alt+c in the window: not rank C
  EXPECT_EQ(decode("\x1B"
                   "q"),
            "");
  EXPECT_EQ(decode("\x1B"
                   "ca"),
            "a");
}

TEST(KeyDecoder, EscAloneIsQuitAndDoesNotEatTheNextKey) {
  EXPECT_EQ(decode("\x1B"), "q");  // Esc, then nothing in that read: as Esc in the window
  KeyDecoder d;
  EXPECT_EQ(d.feed(0x1B), std::nullopt);
  EXPECT_EQ(d.idle(), 'q');
  EXPECT_EQ(d.feed('t'), 't');  // the next read's key is its own
  EXPECT_EQ(d.idle(), std::nullopt);
  EXPECT_EQ(decode("\x1B\x1B"), "q");
}

}  // namespace
