#pragma once
// The one home of the nominal device tick rate (design §7): the firmware build's default (CMake's
// HMP_TICK_HZ starts from it) and what host code assumes until a device's HelloReply gives its own.
#include <cstdint>

namespace hmp::synth {

inline constexpr std::uint32_t kNominalTickHz = 1000;

}  // namespace hmp::synth
