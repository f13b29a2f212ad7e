// The controller as a DUT runs it, wired once for every place it runs: the flight controller,
// the tactile front end fed by the sensor nodes' samples, and the grasp admittance, stepped
// together once per control period. It owns every state and keeps no clock; inputs arrive through
// the On* calls with the time they belong to, and Step returns what the DUT sends back. Portable
// like the rest of dut_fw: no allocation, the scalar a template parameter (float on the target).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "dut_fw/flight_controller.h"
#include "dut_fw/grasp_controller.h"
#include "dut_fw/tactile_processor.h"

namespace hilrig::dut_fw {

template <typename S>
struct DutCoreParams {
  FlightControllerParams<S> flight;
  std::optional<TactileProcessorParams<S>> tactile;  // empty: the scene has no tactile nodes
  GraspAdmittanceParams<S> grasp;
  // false: the ablation that keeps the tactile force out of the admittance and the thrust.
  bool external_force_in_position_loop = true;
};

template <typename S>
struct DutCoreOutput {
  std::array<S, 4> rotor_thrust_n = {S(0), S(0), S(0), S(0)};
  bool armed = false;
  S servo_angle_rad = S(0);
  Vec3<S> estimated_position_m = Vec3<S>::Zero();
  bool tactile_ready = false;
  S grasp_force_estimate_n = S(0);
  Vec3<S> external_force_world_n = Vec3<S>::Zero();
  // Each pad's decoded force in its sensor frame (nodes 1..6); zero without tactile nodes.
  std::array<Vec3<S>, 6> tactile_force_sensor_n = {Vec3<S>::Zero(), Vec3<S>::Zero(),
                                                   Vec3<S>::Zero(), Vec3<S>::Zero(),
                                                   Vec3<S>::Zero(), Vec3<S>::Zero()};
};

template <typename S>
class DutCore {
 public:
  explicit DutCore(const DutCoreParams<S>& params)
      : controller_(params.flight),
        grasp_params_(params.grasp),
        grasp_params_valid_(GraspParamsValid(grasp_params_)),
        external_force_in_position_loop_(params.external_force_in_position_loop),
        tactile_params_(params.tactile) {
    reference_.position_m.setZero();
    reference_.velocity_m_s.setZero();
    reference_.acceleration_m_s2.setZero();
    reference_.yaw_rad = S(0);
  }

  void OnImu(const Vec3<S>& gyro_rad_s, const Vec3<S>& accel_m_s2, std::int64_t time_ns) {
    controller_.OnImu(state_, gyro_rad_s, accel_m_s2, time_ns);
  }

  void OnVio(const Vec3<S>& position_m, const Quat<S>& orientation, std::int64_t capture_time_ns) {
    controller_.OnVio(state_, position_m, orientation, capture_time_ns);
  }

  void OnSetpoint(const Reference<S>& reference, const GraspCommand<S>& grasp) {
    reference_ = reference;
    grasp_command_ = grasp;
  }

  // A sensor node's sample; node tactile_bus::kReferenceNodeId is the unloaded reference
  // magnetometer.
  void OnSensorSample(std::uint8_t node_id, const std::array<std::uint16_t, 3>& codes,
                      std::uint8_t sequence, bool saturated, std::int64_t time_ns) {
    if (!tactile_params_) return;
    summary_dirty_ = true;
    if (node_id == tactile_bus::kReferenceNodeId) {
      OnReferenceSample(*tactile_params_, tactile_state_, codes, sequence, saturated, time_ns);
    } else {
      OnTactileSample(*tactile_params_, tactile_state_, node_id, codes, sequence, saturated,
                      time_ns);
    }
  }

  // One control step at `now_ns`, `dt_s` after the previous one.
  DutCoreOutput<S> Step(std::int64_t now_ns, S dt_s) {
    const TactileForces tactile = SummarizeForces(now_ns);
    const Vec3<S> loop_force_n =
        external_force_in_position_loop_ ? tactile.external_world_n : Vec3<S>::Zero();
    controller_.Step(state_, reference_, loop_force_n, dt_s, flight_output_);
    const GraspOutput<S> grasp =
        grasp_params_valid_
            ? StepGraspControllerWithValidParams(grasp_params_, grasp_state_, grasp_command_,
                                                 tactile.grasp_n, tactile.valid, dt_s)
            : StepGraspController(grasp_params_, grasp_state_, grasp_command_, tactile.grasp_n,
                                  tactile.valid, dt_s);
    DutCoreOutput<S> out;
    out.rotor_thrust_n = flight_output_.rotor_thrust_n;
    out.armed = flight_output_.armed;
    out.servo_angle_rad = grasp.servo_angle_rad;
    out.estimated_position_m = state_.estimator.position_m;
    out.tactile_ready = tactile.valid;
    out.grasp_force_estimate_n = tactile.grasp_n;
    out.external_force_world_n = tactile.external_world_n;
    if (tactile_params_) {
      for (std::size_t i = 0; i < out.tactile_force_sensor_n.size(); ++i) {
        out.tactile_force_sensor_n[i] = tactile_state_.nodes[i].force_sensor_n;
      }
    }
    return out;
  }

  const TactileProcessorState<S>& tactile_state() const { return tactile_state_; }
  bool has_tactile() const { return tactile_params_.has_value(); }

 private:
  // The front end's sums at `now_ns`, rotated into the world with the estimated attitude; nothing
  // until every pad is zeroed and fresh.
  struct TactileForces {
    Vec3<S> external_world_n = Vec3<S>::Zero();
    S grasp_n = S(0);
    bool valid = false;
  };

  TactileForces SummarizeForces(std::int64_t now_ns) {
    TactileForces forces;
    if (!tactile_params_) return forces;
    // The sums only change with a new sample or when a node goes stale, so they are kept between
    // control steps (the 50 Hz nodes feed a 1 kHz loop).
    if (summary_dirty_ || now_ns > summary_valid_until_ns_) {
      summary_ = SummarizeTactile(*tactile_params_, tactile_state_, now_ns);
      summary_valid_until_ns_ = TactileSummaryValidUntil(*tactile_params_, tactile_state_, now_ns);
      summary_dirty_ = false;
    }
    if (!summary_.ready) return forces;
    forces.external_world_n =
        Rotate<S>(state_.estimator.orientation, summary_.external_force_body_n);
    forces.grasp_n = summary_.grasp_force_n;
    forces.valid = true;
    return forces;
  }

  FlightController<S> controller_;
  FlightControllerState<S> state_;
  Reference<S> reference_;
  FlightControllerOutput<S> flight_output_;  // filled in place by every control step
  const GraspAdmittanceParams<S> grasp_params_;
  // Checked once: the parameters never change, so a valid set takes the step without the per-step
  // check and an invalid one the checked step (which commands the open angle and counts every step
  // as rejected).
  const bool grasp_params_valid_;
  GraspControllerState<S> grasp_state_;
  GraspCommand<S> grasp_command_;
  bool external_force_in_position_loop_;
  std::optional<TactileProcessorParams<S>> tactile_params_;
  TactileProcessorState<S> tactile_state_{};
  TactileSummary<S> summary_;
  bool summary_dirty_ = true;
  std::int64_t summary_valid_until_ns_ = 0;
};

}  // namespace hilrig::dut_fw
