#pragma once
// Parsing of envelope choices given on the command line: `--instrument NAME` and
// `--adsr attack=..,decay=..,sustain=..,release=..,final=..` (design §3: attack/decay/release in ms,
// sustain/final in % of the peak).
#include <string>

#include "shared/envelope/envelope.hpp"

namespace hmp::haptics {

// Throws BadInput naming the offending key or value.
envelope::Adsr parse_adsr(const std::string& text);
// A built-in preset by name (case-insensitive). Throws BadInput listing the known names.
envelope::Adsr builtin_by_name(const std::string& name);
// "organ, flute, …" for messages and --help.
std::string builtin_names();

}  // namespace hmp::haptics
