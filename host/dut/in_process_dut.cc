#include "host/dut/in_process_dut.h"

#include <variant>

namespace hilrig::host {

InProcessDut::InProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> bus,
                           double control_period_s)
    : controller_(firmware.flight),
      grasp_params_(firmware.grasp),
      external_force_in_position_loop_(firmware.external_force_in_position_loop),
      tactile_params_(firmware.tactile),
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
  grasp_command_.mode =
      message.grasp_regulate ? dut_fw::GraspMode::kForce : dut_fw::GraspMode::kOpen;
  grasp_command_.force_n = message.grasp_force_n;
  grasp_command_.reference_angle_rad = message.grasp_reference_angle_rad;
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
    summary_dirty_ = true;
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

InProcessDut::TactileForces InProcessDut::SummarizeForces(std::int64_t now_ns) {
  TactileForces forces;
  if (!tactile_params_) return forces;
  if (summary_dirty_ || now_ns > summary_valid_until_ns_) {
    summary_ = dut_fw::SummarizeTactile(*tactile_params_, tactile_state_, now_ns);
    summary_valid_until_ns_ =
        dut_fw::TactileSummaryValidUntil(*tactile_params_, tactile_state_, now_ns);
    summary_dirty_ = false;
  }
  if (!summary_.ready) return forces;
  forces.external_world_n =
      dut_fw::Rotate<double>(state_.estimator.orientation, summary_.external_force_body_n);
  forces.grasp_n = summary_.grasp_force_n;
  forces.valid = true;
  return forces;
}

rig::Result<ActuatorMessage> InProcessDut::Step(std::uint64_t tick, std::int64_t now_ns) {
  DrainBus(now_ns);
  const TactileForces tactile = SummarizeForces(now_ns);
  const Eigen::Vector3d loop_force_n =
      external_force_in_position_loop_ ? tactile.external_world_n : Eigen::Vector3d::Zero();
  const auto output = controller_.Step(state_, reference_, loop_force_n, control_period_s_);
  const auto grasp = dut_fw::StepGraspController(grasp_params_, grasp_state_, grasp_command_,
                                                 tactile.grasp_n, tactile.valid, control_period_s_);
  ActuatorMessage command;
  command.stamp = {commands_sent_++, now_ns};
  command.answers_sequence = tick;
  command.rotor_thrust_n = output.rotor_thrust_n;
  command.armed = output.armed;
  command.servo_angle_rad = grasp.servo_angle_rad;
  command.estimated_position_m = state_.estimator.position_m;
  command.tactile_ready = tactile.valid;
  command.grasp_force_estimate_n = tactile.grasp_n;
  command.external_force_world_n = tactile.external_world_n;
  if (tactile_params_) {
    for (std::size_t i = 0; i < command.tactile_force_sensor_n.size(); ++i) {
      command.tactile_force_sensor_n[i] = tactile_state_.nodes[i].force_sensor_n;
    }
  }
  return command;
}

}  // namespace hilrig::host
