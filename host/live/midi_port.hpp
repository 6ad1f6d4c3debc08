#pragma once
// MIDI ports (module "midiport", host/live/rtmidi/: RtMidi over the ALSA sequencer and JACK): the inputs
// `hmp live` reads and the outputs `hmp play --midi-out` writes, so that only those load the libraries.
// Errors come back as text, never as exceptions.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hmp::live {

// The MIDI systems a port can be on.
enum class MidiApi { alsa, jack };
const char* name(MidiApi api);

// Whether the system's port `port_name` is one the user named with `asked`: it has `asked` in its name (the
// first such port is the one opened).
bool named_like(const std::string& port_name, const std::string& asked);
// "no jack MIDI output port named like 'fluid' (hmp live --list shows them)": what a back-end says when
// no port of that direction (`input` true: an input) is named_like() `port`.
std::string no_port_named(MidiApi api, bool input, const std::string& port);
// What a port of our own that other programs connect to is called on the status line.
std::string own_port_description(MidiApi api);

struct MidiPortInfo {
  MidiApi api = MidiApi::alsa;
  std::string name;  // as the system names it, e.g. "Midi Through:Midi Through Port-0 14:0"
};

// Called on the back-end's own thread for every message, whole (status byte first).
using MidiReceive = void (*)(void* context, const std::uint8_t* bytes, std::size_t size);

// An open input port: messages flow to the MidiReceive until it is destroyed.
class MidiInput {
 public:
  virtual ~MidiInput() = default;
  virtual std::string name() const = 0;  // what was opened, for the status line
  // Whether the port is still there (a keyboard unplugged, a client gone, the JACK server stopped).
  virtual bool present() const = 0;
};

// An open output port: each message goes out at once, whole and in order.
class MidiOutput {
 public:
  virtual ~MidiOutput() = default;
  virtual std::string name() const = 0;
  // false when the back-end refused it (the port gone); `error` then says why.
  virtual bool send(const std::uint8_t* bytes, std::size_t size, std::string& error) = 0;
};

class MidiPortBackend {
 public:
  static constexpr const char* kModule = "midiport";
  static constexpr int kAbi = 2;

  // The input ports of one system. Non-empty `error`: that system could not be asked (no ALSA sequencer,
  // no JACK server running), and the list is empty.
  virtual std::vector<MidiPortInfo> inputs(MidiApi api, std::string& error) const = 0;
  // Opens the port whose name contains `port` (the first one), or with `port` empty a port of our own
  // named "hmp" that other programs connect to. Null and `error` says why.
  virtual std::unique_ptr<MidiInput> open(MidiApi api, const std::string& port, MidiReceive receive, void* context,
                                          std::string& error) const = 0;
  // The output ports of one system (other programs' inputs: a synthesizer, a DAW's track), as inputs().
  virtual std::vector<MidiPortInfo> outputs(MidiApi api, std::string& error) const = 0;
  // Opens the output port whose name contains `port` (the first one), or with `port` empty a port of our
  // own named "hmp" that other programs connect to. Null and `error` says why.
  virtual std::unique_ptr<MidiOutput> open_output(MidiApi api, const std::string& port, std::string& error) const = 0;

 protected:
  ~MidiPortBackend() = default;  // one static object in the module, never deleted through this
};

// JACK where a server runs (a DAW's world), else the ALSA sequencer.
MidiApi default_api(const MidiPortBackend& b);

// The module, loaded on first use; null (and `why`) when it cannot be had.
const MidiPortBackend* midi_port_backend(std::string* why = nullptr);

}  // namespace hmp::live
