#include "host/audio/audio_options.hpp"

#include <cstdio>

namespace hmp::audio {

void print_warning(const std::string& message) { std::fprintf(stderr, "warning: %s\n", message.c_str()); }

}  // namespace hmp::audio
