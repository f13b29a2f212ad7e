// Commands a DUT sends that the plant cannot take. A NaN or infinite rotor thrust or servo angle
// is not a command: a rotor model that clamps it, or a servo that saturates it, would turn a
// controller's blow-up into a quiet hover on the ground, and the run would pass. The runner refuses
// such a command (the previous one stays applied), counts it here, and fails the run, or stops it
// where the scene says so (simulation.dut_fault: DUT_FAULT_STOP).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "host/link/hil_messages.h"
#include "proto/report.pb.h"

namespace hilrig::host {

// The first of the command's actuator fields that is not finite, as "rotor_thrust_n[2] = nan"
// or "servo_angle_rad = inf"; nothing when every one is finite. The telemetry fields (estimates)
// are not commands and are not looked at. O(1); cannot fail.
std::optional<std::string> NonFiniteCommandField(const ActuatorMessage& command);

class DutFaultTally {
 public:
  // Counts one refused command, `field` its first bad field, at simulated `time_s`.
  void Count(std::string field, double time_s);
  std::uint64_t count() const { return faults_.non_finite_commands(); }
  // What the report carries; unset (nullopt) when nothing was counted.
  std::optional<proto::DutFaults> Report() const;

 private:
  proto::DutFaults faults_;
};

}  // namespace hilrig::host
