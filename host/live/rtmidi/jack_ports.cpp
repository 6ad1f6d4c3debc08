#include "host/live/rtmidi/jack_ports.hpp"

#include "host/live/midi_port.hpp"

namespace hmp::live {

std::string first_jack_port_named_like(jack_client_t* client, const std::string& port, unsigned long flags) {
  std::string found;
  const char** ports = jack_get_ports(client, nullptr, JACK_DEFAULT_MIDI_TYPE, flags);
  for (const char** p = ports; p != nullptr && *p != nullptr && found.empty(); ++p) {
    if (named_like(*p, port)) found = *p;
  }
  jack_free(static_cast<void*>(ports));
  return found;
}

}  // namespace hmp::live
