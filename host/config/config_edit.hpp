#pragma once
// Edits of the user's config file that keep everything else in it as written (comments, order,
// spacing): what `hmp calibrate` saves.
#include <string>
#include <string_view>

namespace hmp::config {

// `toml` with [device] peak_force_n set to `newtons`, everything else kept as it is: the key's line is
// replaced, or added under [device], or a [device] table is appended. Throws BadInput when the key is
// written in a form this does not edit (a dotted key or an inline table).
std::string with_peak_force(std::string_view toml, double newtons);

}  // namespace hmp::config
