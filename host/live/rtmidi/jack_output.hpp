#pragma once
// A MIDI output on JACK written straight on libjack. RtMidi 5's JACK output frees the buffer its process
// callback reads before it closes its client, so a program that closes it while JACK runs a cycle can
// crash (seen: a segfault in jack_ringbuffer_peek on a loaded machine). Here the client is closed first,
// which stops its process thread, and only then is the buffer freed.
#include <memory>
#include <string>

#include "host/live/midi_port.hpp"

namespace hmp::live {

// Opens a JACK MIDI output connected to the first input port whose name contains `port`, or with `port`
// empty a port of our own named "hmp" that other programs connect to. Null and `error` says why.
std::unique_ptr<MidiOutput> open_jack_output(const std::string& port, std::string& error);

}  // namespace hmp::live
