#pragma once
// MIDI key numbers and their names in scientific pitch notation, C4 = key 60 (middle C), sharps written
// as C#4 and read also as flats (Db4).
#include <optional>
#include <string>
#include <string_view>

namespace hmp::midi {

std::string key_name(int key);  // "C4"; "-" for a negative key (none)
// A key 0–127 from its name ("A0", "c#4", "Bb-1") or its number ("60"); nullopt for anything else.
std::optional<int> parse_key(std::string_view text);

}  // namespace hmp::midi
