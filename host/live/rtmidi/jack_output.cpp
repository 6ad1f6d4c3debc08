#include "host/live/rtmidi/jack_output.hpp"

#include <jack/jack.h>
#include <jack/midiport.h>
#include <jack/ringbuffer.h>

#include <cstdint>

#include "host/live/rtmidi/jack_client.hpp"

namespace hmp::live {
namespace {

// Messages wait here for the next process cycle, each as its size then its bytes: room for thousands of
// short messages, far more than a song sends in one JACK period.
constexpr std::size_t kRingBytes = 16384;
using Size = std::uint16_t;

class JackOutput final : public MidiOutput {
 public:
  JackOutput() = default;
  JackOutput(const JackOutput&) = delete;
  JackOutput& operator=(const JackOutput&) = delete;
  ~JackOutput() override {
    if (sent_any_) drain();
    // Closing the client stops its process thread; only after that is the buffer it reads freed.
    client_.close();
    if (ring_ != nullptr) jack_ringbuffer_free(ring_);
  }

  bool open(const std::string& port, std::string& error) {
    ring_ = jack_ringbuffer_create(kRingBytes);
    if (ring_ == nullptr) {
      error = "no memory for a JACK MIDI buffer";
      return false;
    }
    return client_.open(port, false, &JackOutput::process, this, error);
  }

  std::string name() const override { return client_.description(); }

  bool send(const std::uint8_t* bytes, std::size_t size, std::string& error) override {
    if (size == 0) return true;
    if (size > kRingBytes / 2) {
      error = "a MIDI message of " + std::to_string(size) + " bytes is more than JACK's buffer here takes";
      return false;
    }
    // The process callback makes room within a cycle or two.
    if (!client_.wait_until([&] { return jack_ringbuffer_write_space(ring_) >= sizeof(Size) + size; })) {
      error = client_.gone() ? "the JACK server stopped" : "the JACK server took no MIDI for 0.2 s";
      return false;
    }
    const auto header = static_cast<Size>(size);
    jack_ringbuffer_write(ring_, reinterpret_cast<const char*>(&header), sizeof header);
    jack_ringbuffer_write(ring_, reinterpret_cast<const char*>(bytes), size);
    sent_any_ = true;
    return true;
  }

 private:
  // What was sent last (a song's closing all-notes-off) reaches the ports connected before the client
  // closes: the process callback takes it within a cycle, and the ports that read it have it a cycle or
  // two later. Cycles counted, not timed: on a busy machine the server's cycles come late, and a wait of
  // two periods' time lost a whole batch in 1 of 3,000 closes here.
  void drain() const {
    client_.wait_until([&] { return jack_ringbuffer_read_space(ring_) == 0; });
    client_.wait_cycles(3);
  }

  // On JACK's process thread: every whole message waiting goes out at the cycle's first frame, in order;
  // those the port's buffer has no room for this cycle wait for the next.
  static int process(jack_nframes_t frames, void* self) {
    auto* me = static_cast<JackOutput*>(self);
    void* buffer = jack_port_get_buffer(me->client_.port(), frames);
    jack_midi_clear_buffer(buffer);
    Size size = 0;
    while (jack_ringbuffer_peek(me->ring_, reinterpret_cast<char*>(&size), sizeof size) == sizeof size &&
           jack_ringbuffer_read_space(me->ring_) >= sizeof size + size) {
      jack_midi_data_t* data = jack_midi_event_reserve(buffer, 0, size);
      if (data == nullptr) break;
      jack_ringbuffer_read_advance(me->ring_, sizeof size);
      jack_ringbuffer_read(me->ring_, reinterpret_cast<char*>(data), size);
    }
    return 0;
  }

  jack_ringbuffer_t* ring_ = nullptr;  // created before the client: the callback never sees null
  bool sent_any_ = false;
  JackMidiClient client_;
};

}  // namespace

std::unique_ptr<MidiOutput> open_jack_output(const std::string& port, std::string& error) {
  auto out = std::make_unique<JackOutput>();
  if (!out->open(port, error)) return nullptr;
  return out;
}

}  // namespace hmp::live
