#include "host/audio/audio_backend.hpp"

#include "host/modules/module_loader.hpp"

namespace hmp::audio {

const AudioBackend* audio_backend(std::string* why) { return modules::backend<AudioBackend>(why); }

std::uint64_t audio_driver_attempts() {
  const auto* loaded = static_cast<const AudioBackend*>(modules::find_loaded(AudioBackend::kModule));
  return loaded != nullptr ? loaded->driver_attempts() : 0;
}

}  // namespace hmp::audio
