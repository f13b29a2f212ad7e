// The dut_fw flight controller running inside the harness process, in lockstep. It is driven only
// through the DutPort messages and its own CAN bus endpoint, exactly what a DUT in another process
// or on real hardware gets, so moving it out of process later changes the transport, not the loop.
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

class InProcessDut final : public DutPort {
 public:
  // `bus` is the DUT's own endpoint on the CAN bus; `control_period_s` is its control step;
  // `firmware.tactile` configures the tactile front end (empty: the scene has no tactile nodes,
  // and reference magnetometer frames are only counted).
  InProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> bus,
               double control_period_s);

  void SendImu(const ImuMessage& message) override;
  void SendVio(const VioMessage& message) override;
  void SendSetpoint(const SetpointMessage& message) override;
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  DutCounters counters() const override;
  std::string description() const override { return "in-process dut_fw (double)"; }

 private:
  void DrainBus(std::int64_t now_ns);
  // The tactile front end's sums at `now_ns`, rotated into the world with the estimated attitude;
  // nothing until every pad is zeroed and fresh.
  struct TactileForces {
    Eigen::Vector3d external_world_n = Eigen::Vector3d::Zero();
    double grasp_n = 0;
    bool valid = false;
  };
  TactileForces SummarizeForces(std::int64_t now_ns);

  dut_fw::FlightController<double> controller_;
  dut_fw::FlightControllerState<double> state_;
  dut_fw::Reference<double> reference_;
  dut_fw::GraspAdmittanceParams<double> grasp_params_;
  dut_fw::GraspControllerState<double> grasp_state_;
  dut_fw::GraspCommand<double> grasp_command_;
  bool external_force_in_position_loop_;
  std::optional<dut_fw::TactileProcessorParams<double>> tactile_params_;
  dut_fw::TactileProcessorState<double> tactile_state_{};
  // The front end's sums only change with a new sample or when a node goes stale, so they are
  // kept between control steps (the 50 Hz nodes feed a 1 kHz loop).
  dut_fw::TactileSummary<double> summary_;
  bool summary_dirty_ = true;
  std::int64_t summary_valid_until_ns_ = 0;
  std::unique_ptr<rig::CanBus> bus_;
  double control_period_s_;
  std::vector<rig::TimedCanFrame> received_;
  rig::TactileLinkMonitor link_monitor_;
  DutCounters counters_;
  std::uint64_t commands_sent_ = 0;
};

}  // namespace hilrig::host
