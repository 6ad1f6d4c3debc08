#include "host/live/rtmidi/jack_input.hpp"

#include <jack/jack.h>
#include <jack/midiport.h>

#include <atomic>
#include <cstdint>

#include "host/live/rtmidi/jack_ports.hpp"

namespace hmp::live {
namespace {

// Status bytes of what nothing is felt from: system exclusive (its start and its continuation), MIDI time
// code, timing clock and active sensing, which a keyboard or a DAW may send many times a second.
bool ignored(std::uint8_t status) {
  return status == 0xF0 || status == 0xF7 || status == 0xF1 || status == 0xF8 || status == 0xFE;
}

class JackInput final : public MidiInput {
 public:
  JackInput(MidiReceive receive, void* context) : receive_(receive), context_(context) {}
  JackInput(const JackInput&) = delete;
  JackInput& operator=(const JackInput&) = delete;
  // Closing the client stops its process thread: no cycle reads the port or calls receive after this.
  ~JackInput() override {
    if (client_ != nullptr) jack_client_close(client_);
  }

  bool open(const std::string& port, std::string& error) {
    client_ = jack_client_open("hmp", JackNoStartServer, nullptr);
    if (client_ == nullptr) {
      error = "no JACK server running";
      return false;
    }
    if (!port.empty()) {
      source_ = first_jack_port_named_like(client_, port, JackPortIsOutput);
      if (source_.empty()) {
        error = no_port_named(MidiApi::jack, true, port);
        return false;
      }
    }
    port_ = jack_port_register(client_, port.empty() ? "hmp" : "hmp-in", JACK_DEFAULT_MIDI_TYPE, JackPortIsInput, 0);
    if (port_ == nullptr) {
      error = "the JACK server refused a MIDI input port";
      return false;
    }
    jack_set_process_callback(client_, &JackInput::process, this);
    jack_on_shutdown(client_, &JackInput::on_shutdown, this);
    if (jack_activate(client_) != 0) {
      error = "the JACK server did not start our client";
      return false;
    }
    if (!source_.empty() && jack_connect(client_, source_.c_str(), jack_port_name(port_)) != 0) {
      error = "the JACK server did not connect " + source_ + " to us";
      return false;
    }
    name_ = source_.empty() ? own_port_description(MidiApi::jack) : source_;
    return true;
  }

  std::string name() const override { return name_; }
  // Asked of the open client (a client opened for it would cost 10–25 ms of JACK's set-up, in the loop
  // that sends the notes).
  bool present() const override {
    if (gone_) return false;
    return source_.empty() || jack_port_by_name(client_, source_.c_str()) != nullptr;
  }

 private:
  // On JACK's process thread: the cycle's messages, in order.
  static int process(jack_nframes_t frames, void* self) {
    auto* me = static_cast<JackInput*>(self);
    void* buffer = jack_port_get_buffer(me->port_, frames);
    const jack_nframes_t count = jack_midi_get_event_count(buffer);
    for (jack_nframes_t i = 0; i < count; ++i) {
      jack_midi_event_t event;
      if (jack_midi_event_get(&event, buffer, i) != 0 || event.size == 0 || ignored(event.buffer[0])) continue;
      me->receive_(me->context_, event.buffer, event.size);
    }
    return 0;
  }

  static void on_shutdown(void* self) { static_cast<JackInput*>(self)->gone_ = true; }

  MidiReceive receive_;
  void* context_;
  jack_client_t* client_ = nullptr;
  jack_port_t* port_ = nullptr;  // registered before the client is activated: the callback never sees null
  std::string source_;           // the port we read from; "" for our own port
  std::atomic<bool> gone_{false};
  std::string name_;
};

}  // namespace

std::unique_ptr<MidiInput> open_jack_input(const std::string& port, MidiReceive receive, void* context,
                                           std::string& error) {
  auto in = std::make_unique<JackInput>(receive, context);
  if (!in->open(port, error)) return nullptr;
  return in;
}

}  // namespace hmp::live
