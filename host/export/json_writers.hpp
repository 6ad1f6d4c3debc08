#pragma once
// The two JSON documents: Apple Core Haptics (.ahap) and Meta Haptics Studio (.haptic). docs/exports.md.
#include <nlohmann/json.hpp>

#include "host/export/haptic_export.hpp"

namespace hmp::exporting {

// AHAP limits as Apple documents them.
inline constexpr double kAhapMaxEventS = 30.0;          // a continuous event lasts at most 30 s
inline constexpr std::size_t kAhapMaxCurvePoints = 16;  // control points per parameter curve
// Envelope sampling step of both exports, in seconds (rounded to whole ticks).
inline constexpr double kExportStepS = 0.005;

nlohmann::json ahap_json(const ExportSpec& spec);
nlohmann::json meta_haptic_json(const ExportSpec& spec);

}  // namespace hmp::exporting
