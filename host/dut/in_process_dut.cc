#include "host/dut/in_process_dut.h"

#include <type_traits>

namespace hilrig::host {

template <typename S>
BasicInProcessDut<S>::BasicInProcessDut(const BasicDutFirmware<S>& firmware,
                                        std::unique_ptr<rig::CanBus> bus, double control_period_s)
    : controller_(firmware.flight),
      grasp_params_(firmware.grasp),
      grasp_params_valid_(dut_fw::GraspParamsValid(grasp_params_)),
      external_force_in_position_loop_(firmware.external_force_in_position_loop),
      tactile_params_(firmware.tactile),
      bus_(std::move(bus)),
      control_period_s_(S(control_period_s)) {
  reference_.position_m.setZero();
  reference_.velocity_m_s.setZero();
  reference_.acceleration_m_s2.setZero();
  reference_.yaw_rad = 0;
  received_.reserve(64);
}

template <typename S>
std::string BasicInProcessDut<S>::description() const {
  return std::is_same_v<S, float> ? "in-process dut_fw (float)" : "in-process dut_fw (double)";
}

template <typename S>
void BasicInProcessDut<S>::Send(const DutInput& input) {
  counters_.Count(input);
  VisitDutInput(input, [this](const auto& message) { Take(message); });
}

template <typename S>
void BasicInProcessDut<S>::Take(const ImuMessage& message) {
  controller_.OnImu(state_, message.gyro_rad_s.cast<S>(), message.accel_m_s2.cast<S>(),
                    message.stamp.time_ns);
}

template <typename S>
void BasicInProcessDut<S>::Take(const VioMessage& message) {
  controller_.OnVio(state_, message.position_m.cast<S>(), message.orientation.cast<S>(),
                    message.capture_time_ns);
}

template <typename S>
void BasicInProcessDut<S>::Take(const SetpointMessage& message) {
  reference_.position_m = message.position_m.cast<S>();
  reference_.velocity_m_s = message.velocity_m_s.cast<S>();
  reference_.acceleration_m_s2 = message.acceleration_m_s2.cast<S>();
  reference_.yaw_rad = S(message.yaw_rad);
  grasp_command_.mode =
      message.grasp_regulate ? dut_fw::GraspMode::kForce : dut_fw::GraspMode::kOpen;
  grasp_command_.force_n = S(message.grasp_force_n);
  grasp_command_.reference_angle_rad = S(message.grasp_reference_angle_rad);
}

template <typename S>
void BasicInProcessDut<S>::DrainBus(std::int64_t now_ns) {
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

template <typename S>
DutCounters BasicInProcessDut<S>::counters() const {
  DutCounters counters = counters_;
  const rig::TactileNodeCounters link = link_monitor_.Totals();
  counters.sensor_sequence_gaps = link.sequence_gaps;
  counters.sensor_samples_lost = link.lost_samples;
  for (const auto& node : tactile_state_.nodes) counters.tactile_samples_flagged += node.flagged;
  return counters;
}

template <typename S>
typename BasicInProcessDut<S>::TactileForces BasicInProcessDut<S>::SummarizeForces(
    std::int64_t now_ns) {
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
      dut_fw::Rotate<S>(state_.estimator.orientation, summary_.external_force_body_n);
  forces.grasp_n = summary_.grasp_force_n;
  forces.valid = true;
  return forces;
}

template <typename S>
rig::Result<ActuatorMessage> BasicInProcessDut<S>::Step(std::uint64_t tick, std::int64_t now_ns) {
  DrainBus(now_ns);
  const TactileForces tactile = SummarizeForces(now_ns);
  const dut_fw::Vec3<S> loop_force_n =
      external_force_in_position_loop_ ? tactile.external_world_n : dut_fw::Vec3<S>::Zero();
  controller_.Step(state_, reference_, loop_force_n, control_period_s_, output_);
  const dut_fw::GraspOutput<S> grasp =
      grasp_params_valid_
          ? dut_fw::StepGraspControllerWithValidParams(grasp_params_, grasp_state_, grasp_command_,
                                                       tactile.grasp_n, tactile.valid,
                                                       control_period_s_)
          : dut_fw::StepGraspController(grasp_params_, grasp_state_, grasp_command_,
                                        tactile.grasp_n, tactile.valid, control_period_s_);
  ActuatorMessage command;
  command.stamp = {commands_sent_++, now_ns};
  command.answers_sequence = tick;
  for (std::size_t i = 0; i < command.rotor_thrust_n.size(); ++i) {
    command.rotor_thrust_n[i] = double(output_.rotor_thrust_n[i]);
  }
  command.armed = output_.armed;
  command.servo_angle_rad = double(grasp.servo_angle_rad);
  command.estimated_position_m = state_.estimator.position_m.template cast<double>();
  command.tactile_ready = tactile.valid;
  command.grasp_force_estimate_n = double(tactile.grasp_n);
  command.external_force_world_n = tactile.external_world_n.template cast<double>();
  if (tactile_params_) {
    for (std::size_t i = 0; i < command.tactile_force_sensor_n.size(); ++i) {
      command.tactile_force_sensor_n[i] =
          tactile_state_.nodes[i].force_sensor_n.template cast<double>();
    }
  }
  return command;
}

template class BasicInProcessDut<double>;
template class BasicInProcessDut<float>;

}  // namespace hilrig::host
