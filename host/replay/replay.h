// A recorded run replayed on a DUT, open loop: the DUT gets the recorded inputs and CAN frames at
// their recorded times and is stepped at the recorded control ticks (the plant does not run), and
// each command it gives is compared with the one recorded for the same tick, output by output.
// Replaying on the DUT build that made the recording gives no difference; a change in the DUT
// (a gain, a firmware image) shows at the first tick its effect reaches an output.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/mcap/mcap_reader.h"
#include "host/replay/recorded_traffic.h"
#include "host/replay/replay_can_bus.h"
#include "rig/result.h"

namespace hilrig::host {

// What a replay compares, each a number or a vector of the DUT's command.
enum class DutOutput {
  kRotorThrust,
  kArmed,
  kServoAngle,
  kGraspForceEstimate,
  kExternalForce,
  kTactileForce,
  kTactileReady,
  kEstimatedPosition,
};
inline constexpr int kDutOutputCount = 8;

// The command field's name: "rotor_thrust_n", "armed", "servo_angle_rad", ...
const char* DutOutputName(DutOutput output);

// The largest absolute difference between the components of `output` in `a` and `b` (flags count
// as 0 or 1); +inf when a component is NaN in one and not in the other. Never fails.
double OutputDifference(DutOutput output, const ActuatorMessage& a, const ActuatorMessage& b);

struct OutputComparison {
  DutOutput output = DutOutput::kRotorThrust;
  double largest = 0;  // over every compared tick
  std::uint64_t largest_tick = 0;
  std::int64_t largest_time_ns = 0;
  // The first tick whose difference passed the tolerance; nullopt when none did.
  std::optional<std::uint64_t> first_past_tick;
  std::int64_t first_past_time_ns = 0;
};

struct ReplayOutcome {
  double tolerance = 0;
  std::uint64_t inputs = 0;
  std::uint64_t can_frames = 0;
  std::uint64_t steps = 0;
  std::uint64_t commands_compared = 0;
  // Recorded commands for a tick the replay has no command for (its step was not recorded, or
  // came after the command: a real-time recording's skipped steps).
  std::uint64_t commands_unmatched = 0;
  std::vector<OutputComparison> outputs;  // one per DutOutput, in its order
  // The DUT failed to answer a step: the replay stopped there.
  std::optional<rig::Error> dut_failure;
  std::uint64_t dut_failure_tick = 0;
  bool interrupted = false;         // a stop request ended it early
  std::int64_t replayed_to_ns = 0;  // simulated time of the last step replayed

  // The output that parted first (the earliest first tick past the tolerance, the first in
  // DutOutput's order on a tie); nullptr when none did.
  const OutputComparison* FirstParted() const;
  bool differs() const { return dut_failure.has_value() || FirstParted() != nullptr; }
};

// Drives `dut` (started; its bus endpoint is `bus`) with `traffic`'s messages of `contents` in
// their recorded order and compares its commands with the recorded ones, a difference above
// `tolerance` counting. Fails on a message that does not decode; a DUT that fails a step ends
// the replay with dut_failure set. Checks `stop_requested` (may be null) between messages.
// O(messages); holds the replayed commands awaiting their recorded ones only.
rig::Result<ReplayOutcome> ReplayTraffic(const mcap::McapContents& contents,
                                         const RecordedTraffic& traffic, DutPort& dut,
                                         ReplayCanBus& bus, double tolerance,
                                         const std::atomic<bool>* stop_requested);

}  // namespace hilrig::host
