#include "host/dut/in_process_dut.h"

#include <type_traits>

namespace hilrig::host {

template <typename S>
BasicInProcessDut<S>::BasicInProcessDut(const BasicDutFirmware<S>& firmware,
                                        std::unique_ptr<rig::CanBus> bus, double control_period_s)
    : core_(firmware), bus_(std::move(bus)), control_period_s_(S(control_period_s)) {
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
  core_.OnImu(message.gyro_rad_s.cast<S>(), message.accel_m_s2.cast<S>(), message.stamp.time_ns);
}

template <typename S>
void BasicInProcessDut<S>::Take(const VioMessage& message) {
  core_.OnVio(message.position_m.cast<S>(), message.orientation.cast<S>(), message.capture_time_ns);
}

template <typename S>
void BasicInProcessDut<S>::Take(const SetpointMessage& message) {
  dut_fw::Reference<S> reference;
  reference.position_m = message.position_m.cast<S>();
  reference.velocity_m_s = message.velocity_m_s.cast<S>();
  reference.acceleration_m_s2 = message.acceleration_m_s2.cast<S>();
  reference.yaw_rad = S(message.yaw_rad);
  dut_fw::GraspCommand<S> grasp;
  grasp.mode = message.grasp_regulate ? dut_fw::GraspMode::kForce : dut_fw::GraspMode::kOpen;
  grasp.force_n = S(message.grasp_force_n);
  grasp.reference_angle_rad = S(message.grasp_reference_angle_rad);
  core_.OnSetpoint(reference, grasp);
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
    core_.OnSensorSample(sample->node_id, sample->code, sample->sequence,
                         (sample->status & tactile_bus::kSampleSaturated) != 0, timed.time_ns);
  }
}

template <typename S>
DutCounters BasicInProcessDut<S>::counters() const {
  DutCounters counters = counters_;
  counters.front_end_counted = true;
  const rig::TactileNodeCounters link = link_monitor_.Totals();
  counters.sensor_sequence_gaps = link.sequence_gaps;
  counters.sensor_samples_lost = link.lost_samples;
  for (const auto& node : core_.tactile_state().nodes) {
    counters.tactile_samples_flagged += node.flagged;
  }
  return counters;
}

template <typename S>
rig::Result<ActuatorMessage> BasicInProcessDut<S>::Step(std::uint64_t tick, std::int64_t now_ns) {
  if (stopped_) return rig::MakeError("the in-process dut was stopped");
  if (last_tick_ && tick <= *last_tick_) {
    return rig::MakeError("tick " + std::to_string(tick) + " requested after tick " +
                          std::to_string(*last_tick_));
  }
  last_tick_ = tick;
  DrainBus(now_ns);
  const dut_fw::DutCoreOutput<S> out = core_.Step(now_ns, control_period_s_);
  ActuatorMessage command;
  command.stamp = {commands_sent_++, now_ns};
  command.answers_sequence = tick;
  for (std::size_t i = 0; i < command.rotor_thrust_n.size(); ++i) {
    command.rotor_thrust_n[i] = double(out.rotor_thrust_n[i]);
  }
  command.armed = out.armed;
  command.servo_angle_rad = double(out.servo_angle_rad);
  command.estimated_position_m = out.estimated_position_m.template cast<double>();
  command.tactile_ready = out.tactile_ready;
  command.grasp_force_estimate_n = double(out.grasp_force_estimate_n);
  command.external_force_world_n = out.external_force_world_n.template cast<double>();
  for (std::size_t i = 0; i < command.tactile_force_sensor_n.size(); ++i) {
    command.tactile_force_sensor_n[i] = out.tactile_force_sensor_n[i].template cast<double>();
  }
  return command;
}

template class BasicInProcessDut<double>;
template class BasicInProcessDut<float>;

rig::Result<std::unique_ptr<DutPort>> MakeDut(const DutFactory& factory,
                                              const ScenarioConfig& config,
                                              std::unique_ptr<rig::CanBus> bus) {
  if (factory) return factory(config, std::move(bus), ControlPeriodS(config));
  return std::unique_ptr<DutPort>(
      std::make_unique<InProcessDut>(FirmwareFor(config), std::move(bus), ControlPeriodS(config)));
}

}  // namespace hilrig::host
