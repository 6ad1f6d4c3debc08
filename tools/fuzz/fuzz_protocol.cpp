// libFuzzer target for protocol::decode (design §9). Besides the sanitizers' memory and UB checks it
// asserts the codec's round-trip property: whatever decode accepts, encode reproduces byte for byte.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "shared/protocol/protocol.hpp"

namespace protocol = hmp::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Reports are always 64 bytes: shorter inputs are zero-extended (a short transfer is padded the same
  // way), longer ones cut. ASan's redzones around `report` catch any read past its end.
  std::uint8_t report[protocol::kReportSize] = {};
  std::memcpy(report, data, size < sizeof report ? size : sizeof report);

  protocol::Message msg;
  const protocol::ErrorCode e = protocol::decode(report, msg);
  if (protocol::name(e) == nullptr) __builtin_trap();
  if (e != protocol::ErrorCode::none) {
    // decode only reports format errors; direction and semantic codes belong to the receiver.
    if (e == protocol::ErrorCode::wrong_direction || e == protocol::ErrorCode::version_mismatch ||
        e == protocol::ErrorCode::queue_full)
      __builtin_trap();
    return 0;
  }
  protocol::Report again;
  if (!protocol::encode(msg, again)) __builtin_trap();
  if (std::memcmp(again, report, sizeof report) != 0) __builtin_trap();
  if (!(protocol::make(msg.type, msg.seq).type == msg.type)) __builtin_trap();
  return 0;
}
