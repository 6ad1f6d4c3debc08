#pragma once
// What the JACK MIDI input and output share: a client of our own on libjack with one MIDI port, connected
// to another program's port or waiting for others to connect to it.
#include <jack/jack.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

namespace hmp::live {

class JackMidiClient {
 public:
  JackMidiClient() = default;
  JackMidiClient(const JackMidiClient&) = delete;
  JackMidiClient& operator=(const JackMidiClient&) = delete;
  ~JackMidiClient() { close(); }

  // Opens a client named "hmp" with a MIDI port (`input`: one we read, else one we write), calls `process`
  // with `context` every cycle, and connects the port to the first other port of the opposite direction
  // whose name contains `port`, or with `port` empty names it "hmp" for other programs to connect to.
  // Returns once the connection has carried a cycle: a message written at once is not lost to a cycle
  // that ran on the server's graph from before the connection. False and `error` (one line for the user)
  // if any step fails.
  bool open(const std::string& port, bool input, JackProcessCallback process, void* context, std::string& error);
  // Stops the process thread (no cycle runs after this) and closes the client; the destructor does too.
  void close();

  // Registered before the client is activated: the process callback never sees it null.
  jack_port_t* port() const { return port_; }
  // The other program's port we are connected to, or how to find ours.
  std::string description() const;
  // Whether the server still runs our client and the other program's port is still there.
  bool present() const;
  // Whether the server has shut our client down.
  bool gone() const { return gone_; }
  // Waits, polling every millisecond, until `done()` holds, for at most kWaitMs; false if it did not hold
  // by then or the server shut our client down.
  template <class Done>
  bool wait_until(Done done) const {
    for (int waited = 0; !gone_; ++waited) {
      if (done()) return true;
      if (waited == kWaitMs) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
  }
  // Waits until `count` more process cycles have run (wait_until's bounds).
  void wait_cycles(unsigned count) const;

  // A cycle is a few ms: a wait this long means the server is not running our client.
  static constexpr int kWaitMs = 200;

 private:
  static int each_cycle(jack_nframes_t frames, void* self);

  jack_client_t* client_ = nullptr;
  jack_port_t* port_ = nullptr;
  std::string other_;  // the other program's port; "" for our own
  std::atomic<bool> gone_{false};
  std::atomic<unsigned> cycles_{0};  // process cycles run
  JackProcessCallback owner_process_ = nullptr;
  void* owner_ = nullptr;
};

}  // namespace hmp::live
