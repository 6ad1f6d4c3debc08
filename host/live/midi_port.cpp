#include "host/live/midi_port.hpp"

#include "host/modules/module_loader.hpp"

namespace hmp::live {

const char* name(MidiApi api) { return api == MidiApi::jack ? "jack" : "alsa"; }

bool named_like(const std::string& port_name, const std::string& asked) {
  return port_name.find(asked) != std::string::npos;
}

std::string no_port_named(MidiApi api, bool input, const std::string& port) {
  return "no " + std::string(name(api)) + " MIDI " + (input ? "input" : "output") + " port named like '" + port +
         "' (hmp live --list shows them)";
}

std::string own_port_description(MidiApi api) {
  return "hmp (" + std::string(name(api)) + ", for other programs to connect to)";
}

MidiApi default_api(const MidiPortBackend& b) {
  std::string error;
  b.inputs(MidiApi::jack, error);
  return error.empty() ? MidiApi::jack : MidiApi::alsa;
}

const MidiPortBackend* midi_port_backend(std::string* why) { return modules::backend<MidiPortBackend>(why); }

}  // namespace hmp::live
