#include "host/live/rtmidi/jack_client.hpp"

#include "host/live/midi_port.hpp"

namespace hmp::live {
namespace {

// The full name of the first MIDI port with `flags` whose name contains `port`, or "" if none does.
std::string first_port_named_like(jack_client_t* client, const std::string& port, unsigned long flags) {
  std::string found;
  const char** ports = jack_get_ports(client, nullptr, JACK_DEFAULT_MIDI_TYPE, flags);
  for (const char** p = ports; p != nullptr && *p != nullptr && found.empty(); ++p) {
    if (named_like(*p, port)) found = *p;
  }
  jack_free(static_cast<void*>(ports));
  return found;
}

void on_shutdown(void* gone) { static_cast<std::atomic<bool>*>(gone)->store(true); }

}  // namespace

bool JackMidiClient::open(const std::string& port, bool input, JackProcessCallback process, void* context,
                          std::string& error) {
  client_ = jack_client_open("hmp", JackNoStartServer, nullptr);
  if (client_ == nullptr) {
    error = "no JACK server running";
    return false;
  }
  if (!port.empty()) {
    other_ = first_port_named_like(client_, port, input ? JackPortIsOutput : JackPortIsInput);
    if (other_.empty()) {
      error = no_port_named(MidiApi::jack, input, port);
      return false;
    }
  }
  const char* name = port.empty() ? "hmp" : input ? "hmp-in" : "hmp-out";
  port_ = jack_port_register(client_, name, JACK_DEFAULT_MIDI_TYPE, input ? JackPortIsInput : JackPortIsOutput, 0);
  if (port_ == nullptr) {
    error = std::string("the JACK server refused a MIDI ") + (input ? "input" : "output") + " port";
    return false;
  }
  owner_process_ = process;
  owner_ = context;
  jack_set_process_callback(client_, &JackMidiClient::each_cycle, this);
  jack_on_shutdown(client_, &on_shutdown, &gone_);
  if (jack_activate(client_) != 0) {
    error = "the JACK server did not start our client";
    return false;
  }
  if (other_.empty()) return true;
  const char* ours = jack_port_name(port_);
  if (jack_connect(client_, input ? other_.c_str() : ours, input ? ours : other_.c_str()) != 0) {
    error = "the JACK server did not connect " + (input ? other_ + " to us" : "us to " + other_);
    return false;
  }
  // The server takes the new connection into its graph at the start of a cycle: the one after next has it.
  wait_cycles(2);
  return true;
}

int JackMidiClient::each_cycle(jack_nframes_t frames, void* self) {
  auto* me = static_cast<JackMidiClient*>(self);
  me->cycles_.fetch_add(1, std::memory_order_relaxed);
  return me->owner_process_(frames, me->owner_);
}

void JackMidiClient::close() {
  if (client_ != nullptr) jack_client_close(client_);
  client_ = nullptr;
}

std::string JackMidiClient::description() const {
  return other_.empty() ? own_port_description(MidiApi::jack) : other_;
}

void JackMidiClient::wait_cycles(unsigned count) const {
  const unsigned from = cycles_;
  wait_until([&] { return cycles_ - from >= count; });
}

bool JackMidiClient::present() const {
  if (gone_ || client_ == nullptr) return false;
  return other_.empty() || jack_port_by_name(client_, other_.c_str()) != nullptr;
}

}  // namespace hmp::live
