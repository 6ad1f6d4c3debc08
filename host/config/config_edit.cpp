#include "host/config/config_edit.hpp"

#include <fmt/format.h>

#include "host/common/error.hpp"

namespace hmp::config {

std::string with_peak_force(std::string_view toml, double newtons) {
  const std::string line = fmt::format("peak_force_n = {:.5g}", newtons);
  std::string out;
  std::string_view table;  // the current [table] header's name
  bool in_device = false, done = false, seen_device = false;
  std::size_t device_header_end = std::string::npos;
  auto trim = [](std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return std::string_view{};
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
  };
  std::size_t pos = 0;
  while (pos < toml.size()) {
    std::size_t eol = toml.find('\n', pos);
    if (eol == std::string_view::npos) eol = toml.size();
    const std::string_view raw = toml.substr(pos, eol - pos);
    const std::string_view s = trim(raw);
    pos = eol + 1;
    if (s.starts_with('[')) {
      const std::size_t close = s.find(']');
      table = trim(s.substr(1, close == std::string_view::npos ? 0 : close - 1));
      in_device = table == "device";
      out.append(raw).append("\n");
      if (in_device) {
        seen_device = true;
        device_header_end = out.size();
      }
      continue;
    }
    const std::string_view key = trim(s.substr(0, s.find('=')));
    if ((table.empty() && (key.starts_with("device.") || key == "device")) ||
        (in_device && key.starts_with("peak_force_n") && key != "peak_force_n")) {
      throw BadInput("the config sets [device] in a form this cannot edit: write peak_force_n = " +
                     fmt::format("{:.5g}", newtons) + " under [device] by hand");
    }
    if (in_device && key == "peak_force_n" && s.find('=') != std::string_view::npos) {
      const std::size_t hash = s.find('#');
      out.append(line);
      if (hash != std::string_view::npos) out.append("  ").append(s.substr(hash));
      out.append("\n");
      done = true;
      continue;
    }
    out.append(raw).append("\n");
  }
  if (!toml.empty() && !toml.ends_with('\n')) out.pop_back();  // the file's last line as it was
  if (done) return out;
  if (seen_device) return out.insert(device_header_end, line + "\n");
  if (!out.empty() && !out.ends_with('\n')) out.append("\n");
  return out.append(out.empty() ? "" : "\n").append("[device]\n").append(line).append("\n");
}

}  // namespace hmp::config
