#include "host/linked_dut/mavlink_dut.h"

namespace hilrig::host {

rig::Result<void> ValidateMavlinkDutPortOptions(const MavlinkDutPortOptions& options) {
  if (options.link.hitl && options.session.pacing != DutPacing::kRealtime) {
    return rig::MakeError(
        "a MAVLink board runs in real time only: it keeps its own clock (add --realtime)");
  }
  if (!options.link.hitl && options.session.pacing != DutPacing::kLockstep) {
    return rig::MakeError(
        "a MAVLink DUT runs in lockstep only: PX4's simulator contract gives it no clock but the "
        "sensor steps (leave out --realtime)");
  }
  if (auto session = ValidateLinkedDutOptions(options.session); !session) return session.error();
  return ValidateMavlinkDutOptions(options.link);
}

MavlinkDut::MavlinkDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
                       double control_period_s, const MavlinkDutPortOptions& options)
    : LinkedDut(std::make_unique<MavlinkDutLink>(firmware, control_period_s, options.link),
                std::move(runner_bus), options.session),
      options_(options) {}

rig::Result<void> MavlinkDut::Start() {
  if (auto valid = ValidateMavlinkDutPortOptions(options_); !valid) return valid.error();
  return LinkedDut::Start();
}

}  // namespace hilrig::host
