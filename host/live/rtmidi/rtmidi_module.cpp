// The midiport module's entry (hmp-midiport.so): MIDI in and out of the ALSA sequencer through RtMidi
// (Debian's librtmidi); JACK's through our own clients on libjack (jack_input.hpp and jack_output.hpp say
// why not RtMidi's). RtMidi reports errors by throwing RtMidiError; they stop here.
#include <RtMidi.h>
#include <alsa/asoundlib.h>
#include <jack/jack.h>

#include <memory>
#include <string>
#include <vector>

#include "host/live/midi_port.hpp"
#include "host/live/rtmidi/jack_input.hpp"
#include "host/live/rtmidi/jack_output.hpp"
#include "host/modules/module_loader.hpp"

namespace hmp::live {
namespace {

RtMidi::Api rt_api(MidiApi api) { return api == MidiApi::jack ? RtMidi::UNIX_JACK : RtMidi::LINUX_ALSA; }

// The libraries' own messages (ALSA's "open /dev/snd/seq failed", libjack's "Cannot connect to server
// socket") go nowhere: what failed reaches the user once, as our one line.
extern "C" void quiet_alsa(const char*, int, const char*, int, const char*, ...) {}
extern "C" void quiet_jack(const char*) {}
void quiet_libraries() {
  static const bool done = [] {
    snd_lib_error_set_handler(&quiet_alsa);
    jack_set_error_function(&quiet_jack);
    jack_set_info_function(&quiet_jack);
    return true;
  }();
  static_cast<void>(done);
}

// Whether the system can be asked at all, checked before RtMidi (which prints its own failure on
// stderr before it throws): empty, or why not.
std::string unavailable(MidiApi api) {
  quiet_libraries();
  if (api == MidiApi::alsa) {
    snd_seq_t* seq = nullptr;
    const int rc = snd_seq_open(&seq, "default", SND_SEQ_OPEN_INPUT, 0);
    if (rc < 0) return std::string("no ALSA sequencer (") + snd_strerror(rc) + ")";
    snd_seq_close(seq);
    return "";
  }
  jack_status_t status{};
  jack_client_t* client = jack_client_open("hmp-check", JackNoStartServer, &status);
  if (client == nullptr) return "no JACK server running";
  jack_client_close(client);
  return "";
}

// RtMidi's messages name its own functions ("MidiInJack::initialize: JACK server not running?"): the
// part after the function name is what a user can act on.
std::string plain(const std::string& what) {
  const std::size_t colon = what.find(": ");
  return colon == std::string::npos ? what : what.substr(colon + 2);
}

// RtMidi throws what stops a call but only prints a warning for some failures, among them "JACK server
// not running?" (and then lists no port): with this callback every one is kept, and nothing is printed.
struct Errors {
  std::string first;
  static void keep(RtMidiError::Type, const std::string& text, void* self) {
    auto* me = static_cast<Errors*>(self);
    if (me->first.empty()) me->first = plain(text);
  }
};

// Opens `rt` (an RtMidiIn or RtMidiOut) on the first port whose name contains `port`, or with `port`
// empty on a port of our own named "hmp"; the port's name for the user, or "" and `errors` says why.
template <class RtPort>
std::string open_port(RtPort& rt, MidiApi api, const std::string& port, const char* direction, Errors& errors) {
  // Connects to the system first: with no JACK server RtMidi would go on to register a port on no client.
  const unsigned count = rt.getPortCount();
  if (!errors.first.empty()) return "";
  if (port.empty()) {
    rt.openVirtualPort("hmp");
    return own_port_description(api);
  }
  for (unsigned i = 0; i < count; ++i) {
    const std::string candidate = rt.getPortName(i);
    if (!named_like(candidate, port)) continue;
    rt.openPort(i, std::string("hmp-") + direction);
    return candidate;
  }
  if (errors.first.empty()) errors.first = no_port_named(api, direction == std::string("in"), port);
  return "";
}

// The ports an RtMidiIn (inputs) or RtMidiOut (outputs) can open on one system.
template <class RtPort>
std::vector<MidiPortInfo> list_ports(MidiApi api, std::string& error) {
  std::vector<MidiPortInfo> out;
  if (error = unavailable(api); !error.empty()) return out;
  try {
    Errors errors;
    RtPort rt(rt_api(api), "hmp-list");
    rt.setErrorCallback(&Errors::keep, &errors);
    const unsigned count = rt.getPortCount();
    for (unsigned i = 0; i < count; ++i) out.push_back({api, rt.getPortName(i)});
    error = errors.first;
  } catch (const RtMidiError& e) {
    error = plain(e.getMessage());
  }
  if (!error.empty()) out.clear();
  return out;
}

// An input on the ALSA sequencer.
class RtInput final : public MidiInput {
 public:
  RtInput(MidiApi api, MidiReceive receive, void* context)
      : api_(api), in_(rt_api(api), "hmp"), receive_(receive), context_(context) {
    in_.setErrorCallback(&Errors::keep, &errors_);
    in_.ignoreTypes(true, true, true);  // system exclusive, timing (clock), active sensing: nothing to feel
  }
  ~RtInput() override {
    try {
      in_.cancelCallback();
      in_.closePort();
    } catch (const RtMidiError&) {
    }
  }
  // Opens the first port whose name contains `port`; false (and `error`) if none does or it fails.
  bool open(const std::string& port, std::string& error) {
    in_.setCallback(&RtInput::on_message, this);
    name_ = open_port(in_, api_, port, "in", errors_);
    virtual_ = port.empty();
    error = errors_.first;
    return error.empty();
  }
  std::string name() const override { return name_; }
  // Asked of the open sequencer client itself, not a new one, in the loop that sends the notes.
  bool present() const override {
    if (virtual_) return true;
    const unsigned count = in_.getPortCount();
    for (unsigned i = 0; i < count; ++i)
      if (in_.getPortName(i) == name_) return true;
    return false;
  }

 private:
  static void on_message(double, std::vector<unsigned char>* message, void* self) {
    auto* me = static_cast<RtInput*>(self);
    if (message != nullptr && !message->empty()) me->receive_(me->context_, message->data(), message->size());
  }
  MidiApi api_;
  Errors errors_;
  mutable RtMidiIn in_;  // present() lists its ports
  MidiReceive receive_;
  void* context_;
  std::string name_;
  bool virtual_ = false;
};

class RtOutput final : public MidiOutput {
 public:
  explicit RtOutput(MidiApi api) : api_(api), out_(rt_api(api), "hmp") {
    out_.setErrorCallback(&Errors::keep, &errors_);
  }
  ~RtOutput() override {
    try {
      out_.closePort();
    } catch (const RtMidiError&) {
    }
  }
  // As RtInput::open, for the other direction.
  bool open(const std::string& port, std::string& error) {
    name_ = open_port(out_, api_, port, "out", errors_);
    error = errors_.first;
    return error.empty();
  }
  std::string name() const override { return name_; }
  bool send(const std::uint8_t* bytes, std::size_t size, std::string& error) override {
    try {
      out_.sendMessage(bytes, size);
    } catch (const RtMidiError& e) {
      errors_.first = plain(e.getMessage());
    }
    error = errors_.first;
    return error.empty();
  }

 private:
  MidiApi api_;
  Errors errors_;
  RtMidiOut out_;
  std::string name_;
};

class RtMidiBackend final : public MidiPortBackend {
 public:
  std::vector<MidiPortInfo> inputs(MidiApi api, std::string& error) const override {
    return list_ports<RtMidiIn>(api, error);
  }
  std::vector<MidiPortInfo> outputs(MidiApi api, std::string& error) const override {
    return list_ports<RtMidiOut>(api, error);
  }
  std::unique_ptr<MidiOutput> open_output(MidiApi api, const std::string& port, std::string& error) const override {
    if (api == MidiApi::jack) {  // its own client says whether a server runs: no second one to ask
      quiet_libraries();
      return open_jack_output(port, error);
    }
    if (error = unavailable(api); !error.empty()) return nullptr;
    try {
      auto out = std::make_unique<RtOutput>(api);
      if (out->open(port, error)) return out;
    } catch (const RtMidiError& e) {
      error = plain(e.getMessage());
    }
    return nullptr;
  }
  std::unique_ptr<MidiInput> open(MidiApi api, const std::string& port, MidiReceive receive, void* context,
                                  std::string& error) const override {
    if (api == MidiApi::jack) {
      quiet_libraries();
      return open_jack_input(port, receive, context, error);
    }
    if (error = unavailable(api); !error.empty()) return nullptr;
    try {
      auto in = std::make_unique<RtInput>(api, receive, context);
      if (in->open(port, error)) return in;
    } catch (const RtMidiError& e) {
      error = plain(e.getMessage());
    }
    return nullptr;
  }
};

}  // namespace
}  // namespace hmp::live

HMP_DEFINE_MODULE(hmp::live::MidiPortBackend, hmp::live::RtMidiBackend)
