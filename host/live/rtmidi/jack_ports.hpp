#pragma once
// What the JACK input and output share: finding another program's port by part of its name.
#include <jack/jack.h>

#include <string>

namespace hmp::live {

// The full name of the first MIDI port with `flags` (JackPortIsInput: ports we write to; JackPortIsOutput:
// ports we read) whose name contains `port`, or "" if none does.
std::string first_jack_port_named_like(jack_client_t* client, const std::string& port, unsigned long flags);

}  // namespace hmp::live
