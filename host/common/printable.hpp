#pragma once
// Bytes from a user's file or command line quoted in a message: every byte made visible, so that a NUL
// does not cut the message short and invalid UTF-8 or control characters do not reach the terminal raw.
#include <string>
#include <string_view>

namespace hmp {

// Valid UTF-8 text (other than control characters) as it is; `\0`, `\n`, `\r`, `\t` and `\\` escaped;
// any other control character, and every byte that is not part of valid UTF-8, as `\xNN`; the C1
// controls (U+0080–U+009F) as `\u00NN`.
std::string printable(std::string_view bytes);

// A message for one line of the terminal: control characters (a newline included) and bytes that are not
// valid UTF-8 escaped as printable() does, a backslash kept (the message may already hold printable()'s
// escapes), and anything past `max_bytes` cut at a character's start and counted ("… (N bytes more)").
inline constexpr std::size_t kTerminalLineMaxBytes = 1000;
std::string terminal_line(std::string_view message, std::size_t max_bytes = kTerminalLineMaxBytes);

// Whether `bytes` is valid UTF-8: no stray continuation bytes, overlong forms, surrogates or code points
// past U+10FFFF.
bool valid_utf8(std::string_view bytes);

}  // namespace hmp
