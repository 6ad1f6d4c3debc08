#pragma once
// design §6's preset table (the paper's Table 1 and the square envelope), typed in from the document for
// the envelope tests to hold the code to: A, Dc, R in ms, s and r in %. square prints r as "–" (it has
// no release); it is stored as 100 %, no fall.
namespace hmp::test {

struct DesignPreset {
  const char* name;
  double a_ms, dc_ms, r_ms, s_pct, r_pct;
};

inline constexpr DesignPreset kDesignPresets[] = {
    {"organ", 5, 0, 25, 100, 1},       {"flute", 75, 0, 60, 100, 1},           {"harpsichord", 55, 0, 55, 100, 17.39},
    {"guitar", 15, 0, 15, 100, 1.36},  {"trumpet", 30, 110, 100, 32.09, 1},    {"violin", 66, 376, 225, 57.14, 1},
    {"cello", 40, 290, 200, 47.45, 1}, {"contrabass", 55, 355, 225, 52.74, 1}, {"square", 0, 0, 0, 100, 100},
};

}  // namespace hmp::test
