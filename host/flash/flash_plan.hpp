#pragma once
// host/flash/: getting firmware onto a board — planning the flashing tool's command line, the image to
// write (built when stale), and the udev rule that lets users flash and play without root. Which boards
// are plugged in is transport/usb_scan.hpp's business.
//
// flash_plan: which tool writes the image, with which command line, and which Debian package has the
// tool. Pure (no I/O), so that the command lines are tested as they are documented (boards/stm32f407/README.md):
//   dfu      dfu-util -d 0483:df11 -a 0 -s 0x08000000:leave -D IMAGE.bin       (ROM bootloader, BOOT0 high)
//   stlink   st-flash --reset write IMAGE.bin 0x8000000                        (ST-LINK)
//   openocd  openocd -f board/stm32f4discovery.cfg -c "program IMAGE.elf verify reset exit"
#include <optional>
#include <string>
#include <vector>

namespace hmp::flash {

enum class Method { dfu, stlink, openocd };

std::optional<Method> parse_method(const std::string& text);  // "dfu", "stlink", "openocd"
const char* method_name(Method m);

struct Tool {
  const char* program;  // looked up on PATH
  const char* package;  // the Debian package that provides it
};
Tool tool_for(Method m);

// The image file each method takes: the raw .bin (dfu, stlink) or the .elf (openocd).
bool wants_elf(Method m);

// The tool's argv (argv[0] = the program).
std::vector<std::string> command_line(Method m, const std::string& image);

// The command as one line a shell accepts (single-quoted where needed).
std::string shell_line(const std::vector<std::string>& argv);

// The commands that build the image in the source dir: `cmake --preset stm32f407` when the build tree is
// not configured yet, then `cmake --build --preset stm32f407`.
std::vector<std::vector<std::string>> build_commands(bool configured);

// The one-line errors (without "error: "): the tool is not on PATH (names its Debian package); no board
// for the method (how to get one ready). `usb_unavailable`: why USB could not be looked at, or empty —
// the hint is the same either way, the reason is added at the end.
std::string missing_tool_message(Method m);
std::string no_board_message(Method m, const std::string& usb_unavailable);

}  // namespace hmp::flash
