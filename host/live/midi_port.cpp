#include "host/live/midi_port.hpp"

#include "host/modules/module_loader.hpp"

namespace hmp::live {

const char* name(MidiApi api) { return api == MidiApi::jack ? "jack" : "alsa"; }

const MidiPortBackend* midi_port_backend(std::string* why) { return modules::backend<MidiPortBackend>(why); }

}  // namespace hmp::live
