#pragma once
// Song time as people read it on screen (the terminal's status line, the window's and the video's overlay).
#include <cstdint>
#include <string>

namespace hmp {

std::string format_time(std::int64_t us);  // "1:05.3" (minutes, seconds, tenths; negative shows as 0)

}  // namespace hmp
