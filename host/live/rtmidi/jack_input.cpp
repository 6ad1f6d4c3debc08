#include "host/live/rtmidi/jack_input.hpp"

#include <jack/jack.h>
#include <jack/midiport.h>

#include <cstdint>

#include "host/live/rtmidi/jack_client.hpp"

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
  // The client, closed first (its destructor), stops its process thread: no cycle reads the port or
  // calls receive after this.
  ~JackInput() override = default;

  bool open(const std::string& port, std::string& error) {
    return client_.open(port, true, &JackInput::process, this, error);
  }
  std::string name() const override { return client_.description(); }
  // Asked of the open client (a client opened for it would cost 10–25 ms of JACK's set-up, in the loop
  // that sends the notes).
  bool present() const override { return client_.present(); }

 private:
  // On JACK's process thread: the cycle's messages, in order.
  static int process(jack_nframes_t frames, void* self) {
    auto* me = static_cast<JackInput*>(self);
    void* buffer = jack_port_get_buffer(me->client_.port(), frames);
    const jack_nframes_t count = jack_midi_get_event_count(buffer);
    for (jack_nframes_t i = 0; i < count; ++i) {
      jack_midi_event_t event;
      if (jack_midi_event_get(&event, buffer, i) != 0 || event.size == 0 || ignored(event.buffer[0])) continue;
      me->receive_(me->context_, event.buffer, event.size);
    }
    return 0;
  }

  MidiReceive receive_;
  void* context_;
  JackMidiClient client_;  // last: destroyed first
};

}  // namespace

std::unique_ptr<MidiInput> open_jack_input(const std::string& port, MidiReceive receive, void* context,
                                           std::string& error) {
  auto in = std::make_unique<JackInput>(receive, context);
  if (!in->open(port, error)) return nullptr;
  return in;
}

}  // namespace hmp::live
