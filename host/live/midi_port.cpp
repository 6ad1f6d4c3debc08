#include "host/live/midi_port.hpp"

#include "host/modules/module_loader.hpp"

namespace hmp::live {

const char* name(MidiApi api) { return api == MidiApi::jack ? "jack" : "alsa"; }

MidiApi default_api(const MidiPortBackend& b) {
  std::string error;
  b.inputs(MidiApi::jack, error);
  return error.empty() ? MidiApi::jack : MidiApi::alsa;
}

const MidiPortBackend* midi_port_backend(std::string* why) { return modules::backend<MidiPortBackend>(why); }

}  // namespace hmp::live
