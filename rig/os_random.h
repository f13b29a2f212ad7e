// Unpredictable bytes from the kernel (getrandom(2)), for what another process on the host must not
// guess: the HIL link's token and the UDP CAN bus's ports. Never for the simulation, whose noise
// comes from the scenario's seed so that a run repeats.
#pragma once

#include <cstdint>
#include <span>

#include "rig/result.h"

namespace hilrig::rig {

// Fills `out`; fails only if the kernel has no randomness to give (an error naming the cause).
Result<void> FillWithOsRandomBytes(std::span<std::uint8_t> out);

}  // namespace hilrig::rig
