// The rig's own controller (DutCore) behind the DUT-side link library's Controller interface
// (dut_link/controller.h): how the STM32 image and dut_emu --serial fly dut_fw, and an example of
// what a team's controller implements. Configure reads the whole DutConfig with dut_fw's decoder
// (refusing what DutCore cannot run) and builds a fresh DutCore; the inputs go in as the link
// carried them, each float widened to S; the tactile bus's sample frames become sensor samples.
// Portable like the rest of dut_fw: the DutCore is held in place (no allocation), no exceptions.
#pragma once

#include <cstdint>
#include <optional>

#include "dut_fw/dut_config_decoder.h"
#include "dut_fw/dut_core.h"
#include "dut_fw/sensor_node.h"
#include "dut_link/controller.h"

namespace hilrig::dut_fw {

template <typename S>
class DutCoreController final : public dut_link::Controller {
 public:
  const char* Configure(const dut_link::RunDescription& run) override {
    core_.reset();
    const ConfigRefusal refusal = DecodeDutConfig(run.config, config_);
    if (refusal != ConfigRefusal::kNone) return Describe(refusal);
    core_.emplace(config_.params);
    dt_s_ = S(config_.control_period_s);
    return nullptr;
  }

  void OnImu(const dut_link::ImuSample& imu) override {
    core_->OnImu(Vec(imu.gyro_rad_s), Vec(imu.accel_m_s2), imu.time_ns);
  }

  void OnVio(const dut_link::VioSample& vio) override {
    const auto& q = vio.orientation_wxyz;
    core_->OnVio(Vec(vio.position_m), Quat<S>(S(q[0]), S(q[1]), S(q[2]), S(q[3])),
                 vio.capture_time_ns);
  }

  void OnSetpoint(const dut_link::Setpoint& setpoint) override {
    Reference<S> reference;
    reference.position_m = Vec(setpoint.position_m);
    reference.velocity_m_s = Vec(setpoint.velocity_m_s);
    reference.acceleration_m_s2 = Vec(setpoint.acceleration_m_s2);
    reference.yaw_rad = S(setpoint.yaw_rad);
    GraspCommand<S> grasp;
    grasp.mode = setpoint.grasp_regulate ? GraspMode::kForce : GraspMode::kOpen;
    grasp.force_n = S(setpoint.grasp_force_n);
    grasp.reference_angle_rad = S(setpoint.grasp_reference_angle_rad);
    core_->OnSetpoint(reference, grasp);
  }

  // Sample frames feed the tactile front end; status frames and other nodes' commands are not
  // the controller's.
  void OnCanFrame(const dut_link::CanFrameIn& frame) override {
    const std::optional<NodeSample> sample = UnpackSampleFrame({frame.id, frame.len, frame.data});
    if (!sample) return;
    core_->OnSensorSample(sample->node_id, sample->code, sample->sequence,
                          (sample->status & tactile_bus::kSampleSaturated) != 0, frame.time_ns);
  }

  dut_link::StepOutput Step(std::int64_t now_ns) override {
    const DutCoreOutput<S> core = core_->Step(now_ns, dt_s_);
    dut_link::StepOutput out;
    for (std::size_t i = 0; i < out.rotor_thrust_n.size(); ++i) {
      out.rotor_thrust_n[i] = float(core.rotor_thrust_n[i]);
    }
    out.armed = core.armed;
    out.servo_angle_rad = float(core.servo_angle_rad);
    out.estimated_position_m = Floats(core.estimated_position_m);
    out.tactile_ready = core.tactile_ready;
    out.grasp_force_estimate_n = float(core.grasp_force_estimate_n);
    out.external_force_world_n = Floats(core.external_force_world_n);
    for (std::size_t i = 0; i < out.pad_force_sensor_n.size(); ++i) {
      out.pad_force_sensor_n[i] = Floats(core.tactile_force_sensor_n[i]);
    }
    return out;
  }

  // The configuration taken and the core built from it; null before a run was configured.
  const DutConfigOnTarget<S>& config() const { return config_; }
  const DutCore<S>* core() const { return core_ ? &*core_ : nullptr; }

 private:
  static Vec3<S> Vec(const dut_link::Vec3f& v) { return Vec3<S>(S(v[0]), S(v[1]), S(v[2])); }
  static dut_link::Vec3f Floats(const Vec3<S>& v) {
    return {float(v.x()), float(v.y()), float(v.z())};
  }

  DutConfigOnTarget<S> config_;
  std::optional<DutCore<S>> core_;
  S dt_s_ = S(0);
};

}  // namespace hilrig::dut_fw
