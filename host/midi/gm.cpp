#include "host/midi/gm.hpp"

#include <charconv>
#include <string>

#include "shared/common/text.hpp"

namespace hmp::midi {
namespace {

// GM1 sound set, program 0 … 127 (GM numbering 1 … 128).
// Laid out by hand (the GM tables, a family to a line), so the formatter leaves it:
// clang-format off
constexpr const char* kProgramNames[128] = {
    // Piano
    "Acoustic Grand Piano", "Bright Acoustic Piano", "Electric Grand Piano", "Honky-tonk Piano",
    "Electric Piano 1", "Electric Piano 2", "Harpsichord", "Clavinet",
    // Chromatic Percussion
    "Celesta", "Glockenspiel", "Music Box", "Vibraphone", "Marimba", "Xylophone", "Tubular Bells",
    "Dulcimer",
    // Organ
    "Drawbar Organ", "Percussive Organ", "Rock Organ", "Church Organ", "Reed Organ", "Accordion",
    "Harmonica", "Tango Accordion",
    // Guitar
    "Acoustic Guitar (nylon)", "Acoustic Guitar (steel)", "Electric Guitar (jazz)",
    "Electric Guitar (clean)", "Electric Guitar (muted)", "Overdriven Guitar", "Distortion Guitar",
    "Guitar Harmonics",
    // Bass
    "Acoustic Bass", "Electric Bass (finger)", "Electric Bass (pick)", "Fretless Bass", "Slap Bass 1",
    "Slap Bass 2", "Synth Bass 1", "Synth Bass 2",
    // Strings
    "Violin", "Viola", "Cello", "Contrabass", "Tremolo Strings", "Pizzicato Strings",
    "Orchestral Harp", "Timpani",
    // Ensemble
    "String Ensemble 1", "String Ensemble 2", "Synth Strings 1", "Synth Strings 2", "Choir Aahs",
    "Voice Oohs", "Synth Voice", "Orchestra Hit",
    // Brass
    "Trumpet", "Trombone", "Tuba", "Muted Trumpet", "French Horn", "Brass Section", "Synth Brass 1",
    "Synth Brass 2",
    // Reed
    "Soprano Sax", "Alto Sax", "Tenor Sax", "Baritone Sax", "Oboe", "English Horn", "Bassoon",
    "Clarinet",
    // Pipe
    "Piccolo", "Flute", "Recorder", "Pan Flute", "Blown Bottle", "Shakuhachi", "Whistle", "Ocarina",
    // Synth Lead
    "Lead 1 (square)", "Lead 2 (sawtooth)", "Lead 3 (calliope)", "Lead 4 (chiff)", "Lead 5 (charang)",
    "Lead 6 (voice)", "Lead 7 (fifths)", "Lead 8 (bass + lead)",
    // Synth Pad
    "Pad 1 (new age)", "Pad 2 (warm)", "Pad 3 (polysynth)", "Pad 4 (choir)", "Pad 5 (bowed)",
    "Pad 6 (metallic)", "Pad 7 (halo)", "Pad 8 (sweep)",
    // Synth Effects
    "FX 1 (rain)", "FX 2 (soundtrack)", "FX 3 (crystal)", "FX 4 (atmosphere)", "FX 5 (brightness)",
    "FX 6 (goblins)", "FX 7 (echoes)", "FX 8 (sci-fi)",
    // Ethnic
    "Sitar", "Banjo", "Shamisen", "Koto", "Kalimba", "Bagpipe", "Fiddle", "Shanai",
    // Percussive
    "Tinkle Bell", "Agogo", "Steel Drums", "Woodblock", "Taiko Drum", "Melodic Tom", "Synth Drum",
    "Reverse Cymbal",
    // Sound Effects
    "Guitar Fret Noise", "Breath Noise", "Seashore", "Bird Tweet", "Telephone Ring", "Helicopter",
    "Applause", "Gunshot",
};

constexpr const char* kFamilyNames[16] = {
    "Piano", "Chromatic Percussion", "Organ", "Guitar", "Bass", "Strings", "Ensemble", "Brass",
    "Reed", "Pipe", "Synth Lead", "Synth Pad", "Synth Effects", "Ethnic", "Percussive", "Sound Effects",
};
// clang-format on

// Sounding ranges (MIDI keys; a transposing instrument's as heard). A family's row holds unless a program of it has a
// row of its own.
struct RangeRow {
  std::uint8_t first, last;  // programs 0–127
  KeySpan keys;
};
constexpr RangeRow kFamilyRanges[] = {
    {0, 7, {21, 108}},      // piano: A0–C8
    {8, 15, {53, 96}},      // chromatic percussion: F3–C7
    {16, 23, {36, 96}},     // organ (one manual), accordion, harmonica: C2–C7
    {24, 31, {40, 88}},     // guitar: E2–E6
    {32, 39, {28, 67}},     // bass: E1–G4
    {40, 47, {28, 103}},    // strings, all of them: E1–G7
    {48, 55, {28, 103}},    // ensembles
    {56, 63, {34, 82}},     // brass: B♭1–B♭5
    {64, 71, {34, 94}},     // reed: B♭1–B♭6
    {72, 79, {60, 96}},     // pipe: C4–C7
    {80, 103, {36, 96}},    // synth lead, pad and effects: a 61-key keyboard
    {104, 111, {48, 84}},   // ethnic: C3–C6
    {112, 119, {36, 84}},   // percussive: C2–C6
    {120, 127, {21, 108}},  // sound effects: the piano's keys
};
constexpr RangeRow kProgramRanges[] = {
    {6, 6, {29, 89}},       // harpsichord: F1–F6
    {9, 9, {79, 108}},      // glockenspiel: G5–C8
    {11, 11, {53, 89}},     // vibraphone: F3–F6
    {12, 12, {45, 96}},     // marimba: A2–C7
    {13, 13, {65, 108}},    // xylophone: F4–C8
    {14, 14, {60, 77}},     // tubular bells: C4–F5
    {40, 40, {55, 105}},    // violin: G3–A7
    {41, 41, {48, 91}},     // viola: C3–G6
    {42, 42, {36, 81}},     // cello: C2–A5
    {43, 43, {28, 67}},     // contrabass: E1–G4
    {46, 46, {24, 103}},    // harp: C1–G7
    {47, 47, {38, 60}},     // timpani: D2–C4
    {52, 54, {40, 84}},     // choir and voices: E2–C6
    {56, 56, {52, 82}},     // trumpet in B♭: E3–B♭5
    {57, 57, {40, 72}},     // trombone: E2–C5
    {58, 58, {26, 65}},     // tuba: D1–F4
    {59, 59, {52, 82}},     // muted trumpet
    {60, 60, {35, 77}},     // French horn in F: B1–F5
    {64, 64, {56, 87}},     // soprano sax: A♭3–E♭6
    {65, 65, {49, 80}},     // alto sax: D♭3–A♭5
    {66, 66, {44, 75}},     // tenor sax: A♭2–E♭5
    {67, 67, {37, 68}},     // baritone sax: D♭2–A♭4
    {68, 68, {58, 91}},     // oboe: B♭3–G6
    {69, 69, {52, 84}},     // English horn: E3–C6
    {70, 70, {34, 75}},     // bassoon: B♭1–E♭5
    {71, 71, {50, 94}},     // clarinet: D3–B♭6
    {72, 72, {74, 108}},    // piccolo: D5–C8
    {73, 73, {60, 98}},     // flute: C4–D7
    {74, 74, {72, 98}},     // recorder (soprano): C5–D7
    {110, 110, {55, 103}},  // fiddle: G3–G7
};

}  // namespace

const char* gm_program_name(std::uint8_t program) { return program < 128 ? kProgramNames[program] : ""; }

KeySpan gm_key_range(std::uint8_t program) {
  for (const RangeRow& r : kProgramRanges)
    if (program >= r.first && program <= r.last) return r.keys;
  for (const RangeRow& r : kFamilyRanges)
    if (program >= r.first && program <= r.last) return r.keys;
  return {};
}

std::optional<std::uint8_t> find_gm_program(std::string_view wanted) {
  int number = 0;
  const auto [end, ec] = std::from_chars(wanted.data(), wanted.data() + wanted.size(), number);
  if (ec == std::errc() && end == wanted.data() + wanted.size())
    return number >= 1 && number <= 128 ? std::optional<std::uint8_t>(number - 1) : std::nullopt;
  for (int p = 0; p < 128; ++p)
    if (text::iequals(std::string(wanted).c_str(), kProgramNames[p])) return static_cast<std::uint8_t>(p);
  return std::nullopt;
}

const char* gm_family_name(std::uint8_t program) { return program < 128 ? kFamilyNames[program / 8] : ""; }

const char* gm_instrument_name(std::uint8_t program, std::uint8_t channel) {
  return channel == 9 ? "Percussion" : gm_program_name(program);
}

}  // namespace hmp::midi
