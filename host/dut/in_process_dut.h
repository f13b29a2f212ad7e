// The dut_fw flight controller running inside the harness process, in lockstep. It is driven only
// through the DutPort messages and its own CAN bus endpoint, exactly what a DUT in another process
// or on real hardware gets, so moving it out of process later changes the transport, not the loop.
// The firmware's scalar is a template parameter: double as on the host, float as the target
// builds it (messages are converted at this boundary, the only place the two meet).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "dut_fw/dut_core.h"
#include "host/dut/dut_port.h"
#include "host/dut/firmware_config.h"
#include "rig/can_bus.h"
#include "rig/tactile_link_monitor.h"

namespace hilrig::host {

template <typename S>
class BasicInProcessDut final : public DutPort {
 public:
  // `bus` is the DUT's own endpoint on the CAN bus; `control_period_s` is its control step;
  // `firmware.tactile` configures the tactile front end (empty: the scene has no tactile nodes,
  // and reference magnetometer frames are only counted).
  BasicInProcessDut(const BasicDutFirmware<S>& firmware, std::unique_ptr<rig::CanBus> bus,
                    double control_period_s);

  // After it, a step is an error, as for every DUT.
  void Stop() override { stopped_ = true; }
  void Send(const DutInput& input) override;
  // Fails for a tick not after the last one, or after Stop.
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  DutCounters counters() const override;
  std::string description() const override;

 private:
  void Take(const ImuMessage& message);
  void Take(const VioMessage& message);
  void Take(const SetpointMessage& message);
  // The rig's controller fuses no magnetometer, barometer or GNSS (VIO gives it heading and
  // position): it takes them and leaves them.
  void Take(const MagnetometerMessage&) {}
  void Take(const BarometerMessage&) {}
  void Take(const GnssMessage&) {}
  void DrainBus(std::int64_t now_ns);

  dut_fw::DutCore<S> core_;
  std::unique_ptr<rig::CanBus> bus_;
  S control_period_s_;
  std::vector<rig::TimedCanFrame> received_;
  rig::TactileLinkMonitor link_monitor_;
  DutCounters counters_;
  std::uint64_t commands_sent_ = 0;
  std::optional<std::uint64_t> last_tick_;
  bool stopped_ = false;
};

using InProcessDut = BasicInProcessDut<double>;
using SinglePrecisionInProcessDut = BasicInProcessDut<float>;

// The DUT of a run or a replay: what `factory` makes for `config` on its bus endpoint `bus`, or
// dut_fw in this process (InProcessDut, flashed with FirmwareFor(config)) when it is unset, both
// at ControlPeriodS(config). Fails when the factory does.
rig::Result<std::unique_ptr<DutPort>> MakeDut(const DutFactory& factory,
                                              const ScenarioConfig& config,
                                              std::unique_ptr<rig::CanBus> bus);

}  // namespace hilrig::host
