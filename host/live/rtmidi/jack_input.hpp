#pragma once
// A MIDI input on JACK written straight on libjack. RtMidi 5's JACK input unregisters its port while its
// process callback may be reading that port's buffer (the callback checks the port for null, then reads
// it, and nothing orders the two against the unregistering thread), so a program that closes it while
// JACK runs a cycle can crash. Here the port lives as long as the client, and the client is closed first,
// which stops its process thread.
#include <memory>
#include <string>

#include "host/live/midi_port.hpp"

namespace hmp::live {

// Opens a JACK MIDI input connected from the first output port whose name contains `port`, or with `port`
// empty a port of our own named "hmp" that other programs connect to. Every message but system exclusive,
// timing (clock, time code) and active sensing goes to `receive`, on JACK's process thread. Null and
// `error` says why.
std::unique_ptr<MidiInput> open_jack_input(const std::string& port, MidiReceive receive, void* context,
                                           std::string& error);

}  // namespace hmp::live
