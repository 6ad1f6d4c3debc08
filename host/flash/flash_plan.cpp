// flash_plan: the flashing tools' command lines, their packages, the image build's commands and the
// one-line messages when a tool or a board is missing. No I/O.
#include "host/flash/flash_plan.hpp"

namespace hmp::flash {

std::optional<Method> parse_method(const std::string& text) {
  if (text == "dfu") return Method::dfu;
  if (text == "stlink") return Method::stlink;
  if (text == "openocd") return Method::openocd;
  return std::nullopt;
}

const char* method_name(Method m) {
  switch (m) {
    case Method::dfu: return "dfu";
    case Method::stlink: return "stlink";
    case Method::openocd: return "openocd";
  }
  return "?";
}

Tool tool_for(Method m) {
  switch (m) {
    case Method::dfu: return {"dfu-util", "dfu-util"};
    case Method::stlink: return {"st-flash", "stlink-tools"};
    case Method::openocd: return {"openocd", "openocd"};
  }
  return {"?", "?"};
}

bool wants_elf(Method m) { return m == Method::openocd; }

std::vector<std::string> command_line(Method m, const std::string& image) {
  switch (m) {
    case Method::dfu:
      // Alternate setting 0 is the internal flash; ":leave" starts the new firmware when done.
      return {"dfu-util", "-d", "0483:df11", "-a", "0", "-s", "0x08000000:leave", "-D", image};
    case Method::stlink: return {"st-flash", "--reset", "write", image, "0x8000000"};
    case Method::openocd:
      return {"openocd", "-f", "board/stm32f4discovery.cfg", "-c", "program " + image + " verify reset exit"};
  }
  return {};
}

std::string shell_line(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) {
    if (!out.empty()) out += ' ';
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./:=@%+,") == std::string::npos;
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += '\'';
  }
  return out;
}

std::vector<std::vector<std::string>> build_commands(bool configured) {
  std::vector<std::vector<std::string>> out;
  if (!configured) out.push_back({"cmake", "--preset", "stm32f407"});
  out.push_back({"cmake", "--build", "--preset", "stm32f407"});
  return out;
}

std::string missing_tool_message(Method m) {
  const Tool t = tool_for(m);
  return std::string(t.program) + " not found — install it: sudo apt install " + t.package;
}

std::string no_board_message(Method m, const std::string& usb_unavailable) {
  std::string out =
      m == Method::dfu
          ? "no STM32 in DFU mode found (0483:df11) — hold BOOT0 high (on the STM32F4DISCOVERY: a jumper from BOOT0 "
            "to VDD), press RESET, and run hmp flash again"
          : "no ST-LINK probe found — connect the board's ST-LINK USB port (CN1 on the STM32F4DISCOVERY)";
  if (!usb_unavailable.empty()) out += " (USB could not be read here: " + usb_unavailable + ")";
  return out;
}

}  // namespace hmp::flash
