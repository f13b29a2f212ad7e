#include "host/runner/dut_faults.h"

#include <cmath>

#include "rig/number_text.h"

namespace hilrig::host {

std::optional<std::string> NonFiniteCommandField(const ActuatorMessage& command) {
  for (std::size_t i = 0; i < command.rotor_thrust_n.size(); ++i) {
    if (!std::isfinite(command.rotor_thrust_n[i])) {
      return "rotor_thrust_n[" + std::to_string(i) +
             "] = " + rig::NumberText(command.rotor_thrust_n[i]);
    }
  }
  if (!std::isfinite(command.servo_angle_rad)) {
    return "servo_angle_rad = " + rig::NumberText(command.servo_angle_rad);
  }
  return std::nullopt;
}

void DutFaultTally::Count(std::string field, double time_s) {
  if (faults_.non_finite_commands() == 0) {
    faults_.set_first_at_s(time_s);
    faults_.set_first_field(std::move(field));
  }
  faults_.set_non_finite_commands(faults_.non_finite_commands() + 1);
}

std::optional<proto::DutFaults> DutFaultTally::Report() const {
  if (faults_.non_finite_commands() == 0) return std::nullopt;
  return faults_;
}

}  // namespace hilrig::host
