#include "host/dut/in_process_dut.h"

#include <variant>

namespace hilrig::host {

InProcessDut::InProcessDut(const dut_fw::FlightControllerParams<double>& params,
                           const std::optional<dut_fw::TactileProcessorParams<double>>& tactile,
                           std::unique_ptr<rig::CanBus> bus, double control_period_s)
    : controller_(params),
      tactile_params_(tactile),
      bus_(std::move(bus)),
      control_period_s_(control_period_s) {
  reference_.position_m.setZero();
  reference_.velocity_m_s.setZero();
  reference_.acceleration_m_s2.setZero();
  reference_.yaw_rad = 0;
  received_.reserve(64);
}

void InProcessDut::SendImu(const ImuMessage& message) {
  ++counters_.imu_messages;
  controller_.OnImu(state_, message.gyro_rad_s, message.accel_m_s2, message.stamp.time_ns);
}

void InProcessDut::SendVio(const VioMessage& message) {
  ++counters_.vio_messages;
  controller_.OnVio(state_, message.position_m, message.orientation, message.capture_time_ns);
}

void InProcessDut::SendSetpoint(const SetpointMessage& message) {
  reference_.position_m = message.position_m;
  reference_.velocity_m_s = message.velocity_m_s;
  reference_.acceleration_m_s2 = message.acceleration_m_s2;
  reference_.yaw_rad = message.yaw_rad;
}

void InProcessDut::DrainBus(std::int64_t now_ns) {
  received_.clear();
  bus_->Receive(now_ns, received_);
  for (const rig::TimedCanFrame& timed : received_) {
    ++counters_.can_frames_received;
    const auto message = link_monitor_.Observe(timed.frame);
    if (!message.ok()) {
      ++counters_.can_frames_rejected;
      continue;
    }
    const auto* sample = std::get_if<rig::TactileSample>(&message.value());
    if (sample == nullptr) continue;  // status frames and other hosts' commands
    ++counters_.sensor_samples;
    if (!tactile_params_) continue;
    const bool saturated = (sample->status & rig::kSampleStatusSaturated) != 0;
    if (sample->node_id == rig::kReferenceNodeId) {
      dut_fw::OnReferenceSample(*tactile_params_, tactile_state_, sample->code, sample->sequence,
                                saturated, timed.time_ns);
    } else {
      dut_fw::OnTactileSample(*tactile_params_, tactile_state_, sample->node_id, sample->code,
                              sample->sequence, saturated, timed.time_ns);
    }
  }
}

DutCounters InProcessDut::counters() const {
  DutCounters counters = counters_;
  const rig::TactileNodeCounters link = link_monitor_.Totals();
  counters.sensor_sequence_gaps = link.sequence_gaps;
  counters.sensor_samples_lost = link.lost_samples;
  return counters;
}

void InProcessDut::FillTactileTelemetry(std::int64_t now_ns, ActuatorMessage& command) const {
  if (!tactile_params_) return;
  const auto summary = dut_fw::SummarizeTactile(*tactile_params_, tactile_state_, now_ns);
  command.tactile_ready = summary.ready;
  for (std::size_t i = 0; i < command.tactile_force_sensor_n.size(); ++i) {
    command.tactile_force_sensor_n[i] = tactile_state_.nodes[i].force_sensor_n;
  }
}

rig::Result<ActuatorMessage> InProcessDut::Step(std::uint64_t tick, std::int64_t now_ns) {
  DrainBus(now_ns);
  const Eigen::Vector3d no_external_force_n = Eigen::Vector3d::Zero();
  const auto output = controller_.Step(state_, reference_, no_external_force_n, control_period_s_);
  ActuatorMessage command;
  command.stamp = {commands_sent_++, now_ns};
  command.answers_sequence = tick;
  command.rotor_thrust_n = output.rotor_thrust_n;
  command.armed = output.armed;
  command.estimated_position_m = state_.estimator.position_m;
  // Tactile force stays out of the position loop until the grasping work wires it in.
  FillTactileTelemetry(now_ns, command);
  return command;
}

}  // namespace hilrig::host
