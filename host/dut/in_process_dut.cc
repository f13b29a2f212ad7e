#include "host/dut/in_process_dut.h"

#include "rig/sensor_frame.h"

namespace hilrig::host {

InProcessDut::InProcessDut(const dut_fw::FlightControllerParams<double>& params,
                           std::unique_ptr<rig::CanBus> bus, double control_period_s)
    : controller_(params), bus_(std::move(bus)), control_period_s_(control_period_s) {
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
    // The reference magnetometer feeds geomagnetic compensation once the tactile chain exists;
    // until then the DUT decodes and counts its samples so a broken frame is still surfaced.
    if (rig::DecodeMagneticSample(timed.frame).ok()) {
      ++counters_.magnetometer_samples;
    } else {
      ++counters_.can_frames_rejected;
    }
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
  return command;
}

}  // namespace hilrig::host
