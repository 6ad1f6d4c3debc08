#include "options.hpp"

#include "console.hpp"
#include "semihosting.hpp"
#include "boards/cortex-m/systick_timer.hpp"
#include "registers.hpp"

namespace hmp::board {
namespace {

bool starts_with(const char* s, const char* prefix) {
  while (*prefix != '\0') {
    if (*s++ != *prefix++) return false;
  }
  return true;
}

// Decimal without sign, at most 9 digits (no overflow); false on anything else.
bool parse_u32(const char* s, std::uint32_t& out) {
  std::uint32_t v = 0;
  int digits = 0;
  for (; *s != '\0'; ++s, ++digits) {
    if (*s < '0' || *s > '9' || digits == 9) return false;
    v = v * 10 + static_cast<std::uint32_t>(*s - '0');
  }
  out = v;
  return digits > 0;
}

bool equals(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) ++a, ++b;
  return *a == *b;
}

bool apply(const char* word, Options& o) {
  if (equals(word, "trace")) {
    o.trace = true;
    return true;
  }
  if (starts_with(word, "hz=")) return parse_u32(word + 3, o.tick_hz) && TickTimer::valid_rate(kCoreHz, o.tick_hz);
  if (starts_with(word, "exit-idle-ms=")) return parse_u32(word + 13, o.exit_idle_ms);
  if (starts_with(word, "listen-after-ms=")) return parse_u32(word + 16, o.listen_after_ms);
  if (equals(word, "link=net") || equals(word, "link=uart")) {
    o.net = word[5] == 'n';
    return true;
  }
  return false;
}

}  // namespace

Options parse_options(char* cmdline) {
  Options o;
  bool first = true;
  for (char* p = cmdline; *p != '\0';) {
    while (*p == ' ') ++p;
    if (*p == '\0') break;
    char* word = p;
    while (*p != '\0' && *p != ' ') ++p;
    if (*p == ' ') *p++ = '\0';
    if (first) {  // the image path
      first = false;
      continue;
    }
    if (!apply(word, o)) {
      o.error = word;
      break;
    }
  }
  return o;
}

Options read_options() {
  static char cmdline[256];  // Options::error points into it
  semihost::get_cmdline(cmdline, sizeof cmdline);
  const Options opt = parse_options(cmdline);
  if (opt.error != nullptr)
    Line()
        .text("bad option: ")
        .text(opt.error)
        .text(" (hz=N trace exit-idle-ms=N listen-after-ms=N link=uart|net)")
        .print();
  return opt;
}

}  // namespace hmp::board
