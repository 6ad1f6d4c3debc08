#include "host/haptics/adsr_option.hpp"

#include <map>
#include <optional>
#include <sstream>

#include "host/common/error.hpp"
#include "host/common/number_text.hpp"

namespace hmp::haptics {

namespace {
double parse_number(const std::string& key, const std::string& value) {
  const std::optional<double> v = finite_number(value);
  if (!v) throw BadInput("--adsr " + key + "=" + value + ": not a finite number");
  return *v;
}
}  // namespace

envelope::Adsr parse_adsr(const std::string& text) {
  // Unspecified keys keep the values of a plain gate: no attack/decay/release, full sustain.
  std::map<std::string, double> values{{"attack", 0}, {"decay", 0}, {"release", 0}, {"sustain", 100}, {"final", 100}};
  std::map<std::string, bool> seen;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw BadInput("--adsr: '" + item + "' is not key=value");
    const std::string key = item.substr(0, eq);
    if (!values.count(key)) {
      throw BadInput("--adsr: unknown key '" + key + "' (known: attack, decay, sustain, release, final)");
    }
    if (seen[key]) throw BadInput("--adsr: key '" + key + "' given twice");
    seen[key] = true;
    values[key] = parse_number(key, item.substr(eq + 1));
  }
  for (const char* ms : {"attack", "decay", "release"}) {
    if (values[ms] < 0 || values[ms] > 1e7) {
      throw BadInput(std::string("--adsr ") + ms + ": must be in [0, 1e7] ms");
    }
  }
  for (const char* pct : {"sustain", "final"}) {
    if (values[pct] < 0 || values[pct] > 100) {
      throw BadInput(std::string("--adsr ") + pct + ": must be in [0, 100] %");
    }
  }
  envelope::Adsr a;
  a.attack_ms = static_cast<float>(values["attack"]);
  a.decay_ms = static_cast<float>(values["decay"]);
  a.release_ms = static_cast<float>(values["release"]);
  a.sustain = static_cast<float>(values["sustain"] / 100.0);
  a.final_ratio = static_cast<float>(values["final"] / 100.0);
  a.shape = envelope::Shape::adsr;
  return a;
}

std::string builtin_names() {
  std::string out;
  for (std::uint8_t i = 0; i < envelope::kBuiltinCount; ++i) {
    if (i) out += ", ";
    out += envelope::name(static_cast<envelope::Preset>(i));
  }
  return out;
}

envelope::Adsr builtin_by_name(const std::string& name) {
  envelope::Preset p;
  if (!envelope::find_builtin(name.c_str(), p)) {
    throw BadInput("unknown instrument '" + name + "' (known: " + builtin_names() + ")");
  }
  return envelope::builtin(p);
}

}  // namespace hmp::haptics
