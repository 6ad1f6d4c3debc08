#include "host/config/config_edit.hpp"

#include <fmt/format.h>

#include "host/common/error.hpp"

namespace hmp::config {

std::string with_peak_force(std::string_view toml, double newtons) {
  const std::string line = fmt::format("peak_force_n = {:.5g}", newtons);
  std::string out;
  std::string_view table;  // the current [table] header's name
  bool in_device = false, done = false, seen_device = false;
  std::size_t last_end = 1;  // what the last line's end added to out
  std::size_t device_header_end = std::string::npos;
  auto trim = [](std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return std::string_view{};
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
  };
  // A UTF-8 byte-order mark (TOML readers skip it) is kept, and not taken as part of the first line.
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  const std::size_t bom = toml.starts_with(kBom) ? kBom.size() : 0;
  out.append(toml.substr(0, bom));
  std::size_t pos = bom;
  // The lines written here end as the file's do (CRLF or LF).
  const std::string_view eol_text = toml.find("\r\n") != std::string_view::npos ? "\r\n" : "\n";
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
      last_end = 1;
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
      out.append(eol_text);
      last_end = eol_text.size();
      done = true;
      continue;
    }
    out.append(raw).append("\n");
    last_end = 1;
  }
  if (toml.size() > bom && !toml.ends_with('\n')) out.resize(out.size() - last_end);  // the last line as it was
  if (done) return out;
  const std::string eol(eol_text);
  if (seen_device) return out.insert(device_header_end, line + eol);
  if (out.size() > bom && !out.ends_with('\n')) out.append(eol);
  return out
      .append(out.size() > bom ? eol : "")  // a blank line after what the file had
      .append("[device]")
      .append(eol)
      .append(line)
      .append(eol);
}

}  // namespace hmp::config
