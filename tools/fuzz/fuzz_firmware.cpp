// libFuzzer target for the firmware core's report handling (design §8: hostile or malformed commands never
// crash the firmware or exceed a limit). The input is a stream of 64-byte host reports (the last one
// zero-padded); the core runs one tick after each and a few hundred at the end, so notes play, fades
// and the watchdog run. Besides the sanitizers it traps when an output sample is not finite or exceeds
// the configured gain, when the device sends a report the protocol cannot decode, or when a report was
// not accounted for.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "firmware/core.hpp"

namespace {

namespace protocol = hmp::protocol;

struct Checks {
  const hmp::fw::Core* core = nullptr;
};

void check_output(void* ctx, float value) {
  const auto* c = static_cast<Checks*>(ctx);
  if (!std::isfinite(value) || std::fabs(value) > c->core->settings().gain) __builtin_trap();
}

bool check_report(void*, const protocol::Report& report) {
  protocol::Message m;
  if (protocol::decode(report, m) != protocol::ErrorCode::none || protocol::is_host_to_device(m.type)) __builtin_trap();
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Checks checks;
  hmp::fw::BoardSeam seam;
  seam.ctx = &checks;
  seam.output = check_output;
  seam.send = check_report;
  hmp::fw::Core core(seam, 1000);
  checks.core = &core;

  std::uint32_t fed = 0;
  for (std::size_t at = 0; at < size; at += protocol::kReportSize) {
    protocol::Report r = {};
    const std::size_t n = size - at < sizeof r ? size - at : sizeof r;
    std::memcpy(r, data + at, n);
    if (!core.on_packet(r)) __builtin_trap();  // one tick per report: the inbox never fills
    ++fed;
    core.on_tick();
    core.poll();  // the background: sends the tick's reports (checked above), prepares voices
  }
  for (int i = 0; i < 300; ++i) {
    core.on_tick();
    core.poll();
  }

  const hmp::fw::Stats& s = core.stats();
  if (s.packets != fed || s.inbox_full != 0 || s.engine_refused != 0) __builtin_trap();
  if ((core.faults() & protocol::fault_output_limit) != 0) __builtin_trap();
  return 0;
}
