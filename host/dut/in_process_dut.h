// The dut_fw flight controller running inside the harness process, in lockstep. It is driven only
// through the DutPort messages and its own CAN bus endpoint, exactly what a DUT in another process
// or on real hardware gets, so moving it out of process later changes the transport, not the loop.
// The firmware's scalar is a template parameter: double as on the host, float as the target
// builds it (messages are converted at this boundary, the only place the two meet).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "dut_fw/flight_controller.h"
#include "dut_fw/grasp_controller.h"
#include "dut_fw/tactile_processor.h"
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

  void Send(const DutInput& input) override;
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  DutCounters counters() const override;
  std::string description() const override;

 private:
  void Take(const ImuMessage& message);
  void Take(const VioMessage& message);
  void Take(const SetpointMessage& message);
  void DrainBus(std::int64_t now_ns);
  // The tactile front end's sums at `now_ns`, rotated into the world with the estimated attitude;
  // nothing until every pad is zeroed and fresh.
  struct TactileForces {
    dut_fw::Vec3<S> external_world_n = dut_fw::Vec3<S>::Zero();
    S grasp_n = S(0);
    bool valid = false;
  };
  TactileForces SummarizeForces(std::int64_t now_ns);

  dut_fw::FlightController<S> controller_;
  dut_fw::FlightControllerState<S> state_;
  dut_fw::Reference<S> reference_;
  dut_fw::FlightControllerOutput<S> output_;  // filled in place by every control step
  const dut_fw::GraspAdmittanceParams<S> grasp_params_;
  // GraspParamsValid(grasp_params_), checked once here: the parameters never change, so a valid
  // set takes the step without the per-step check and an invalid one the checked step (which
  // commands the open angle and counts every step as rejected).
  const bool grasp_params_valid_;
  dut_fw::GraspControllerState<S> grasp_state_;
  dut_fw::GraspCommand<S> grasp_command_;
  bool external_force_in_position_loop_;
  std::optional<dut_fw::TactileProcessorParams<S>> tactile_params_;
  dut_fw::TactileProcessorState<S> tactile_state_{};
  // The front end's sums only change with a new sample or when a node goes stale, so they are
  // kept between control steps (the 50 Hz nodes feed a 1 kHz loop).
  dut_fw::TactileSummary<S> summary_;
  bool summary_dirty_ = true;
  std::int64_t summary_valid_until_ns_ = 0;
  std::unique_ptr<rig::CanBus> bus_;
  S control_period_s_;
  std::vector<rig::TimedCanFrame> received_;
  rig::TactileLinkMonitor link_monitor_;
  DutCounters counters_;
  std::uint64_t commands_sent_ = 0;
};

using InProcessDut = BasicInProcessDut<double>;
using SinglePrecisionInProcessDut = BasicInProcessDut<float>;

}  // namespace hilrig::host
