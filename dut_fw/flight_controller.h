// The whole flight controller of the DUT, wired from its parts: estimator (IMU + delayed VIO) ->
// admittance (external force bends the reference) -> position PD (thrust vector, desired
// attitude; the same external force is fed forward into the thrust) -> attitude P / rate PID
// (body torque) -> mixer (rotor thrusts). The class holds only the constant parameters; everything
// that evolves lives in FlightControllerState, owned by the caller, so a run is reproducible and
// the controller can be stepped from any thread or process.
//
// Default tuning for the 0.556 kg vehicle (J ≈ diag(3e-3, 3e-3, 5e-3) kg m², arm 0.1 m,
// κ = 0.016 m, 4 N per rotor, rotor lag 0.03 s), innermost first so each loop sees the one below
// as fast:
//  - Rate loop ~20 rad/s: K_P = 20·J. K_D = K_P·0.03 s cancels the rotor-lag pole, so the loop
//    looks like a pure integrator up to the 30 Hz derivative filter. K_I puts the PI zero at
//    2.5 rad/s, well below crossover, to trim a grasped object's CoM offset; its clamp holds
//    0.075 N·m. The ω × Jω feed-forward uses the same J.
//  - Attitude loop 7 rad/s roll/pitch (a third of the rate loop, ~70° margin), 4 rad/s yaw (yaw
//    authority is only κ times the thrust spread); rates clamped to 5 / 2 rad/s.
//  - Position loop: 2.5 rad/s, ζ = 0.9 horizontally; 3 rad/s, ζ = 1 vertically (no overshoot into
//    the ground or the object); tilt ≤ 35°; collective in [0.1 m g, 0.9 × 4 rotors × 4 N] so the
//    mixer keeps torque headroom.
//  - Admittance, tuned for grasping: horizontally M = 1 kg, D = 12 N·s/m, K = 36 N/m (critically
//    damped at 6 rad/s, 2.8 cm of give per newton, so a push is yielded to visibly); vertically
//    M = 1 kg, D = 20 N·s/m, K = 100 N/m (critically damped at 10 rad/s, 1 cm of sag per newton:
//    a held 240 g load moves the desired altitude down 2.4 cm). The stiffer z keeps a payload from
//    dragging the vehicle toward the ground or the object below it.
//  - Load feed-forward (load_feedforward): the measured external force is subtracted from the
//    thrust (position_controller.h), so the weight of a held object is carried by feed-forward and
//    not by the position error; with it the admittance offset f/K is the only static position
//    error under a payload (without it the PD adds f/(m Kp): 0.35 m for a 180 g bottle). The
//    switch exists for tests and ablations; the admittance sees the force either way.
//  - Estimator: all poles at 0.9 per VIO update (see state_estimator.h).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "dut_fw/admittance.h"
#include "dut_fw/attitude_controller.h"
#include "dut_fw/mixer.h"
#include "dut_fw/position_controller.h"
#include "dut_fw/state_estimator.h"
#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct FlightControllerParams {
  AdmittanceParams<S> admittance;
  PositionGains<S> position;
  AttitudeGains<S> attitude;
  MixerGeometry<S> mixer;
  EstimatorGains<S> estimator;
  bool load_feedforward = true;  // false: the force bends the reference only (the ablation)
};

template <typename S>
FlightControllerParams<S> DefaultFlightControllerParams(S mass_kg) {
  const Vec3<S> inertia_kg_m2(S(3e-3), S(3e-3), S(5e-3));
  const S rotor_lag_s = S(0.03);
  const S rate_bandwidth_rad_s = S(20);
  const S gravity_m_s2 = S(9.81);

  FlightControllerParams<S> p;
  p.mixer.arm_length_m = S(0.1);
  p.mixer.torque_per_thrust_m = S(0.016);
  p.mixer.max_thrust_per_rotor_n = S(4);

  p.admittance.mass_kg = Vec3<S>::Constant(S(1));
  p.admittance.damping_n_s_per_m = Vec3<S>(S(12), S(12), S(20));
  p.admittance.stiffness_n_per_m = Vec3<S>(S(36), S(36), S(100));

  p.position.kp_per_s2 = Vec3<S>(S(6.25), S(6.25), S(9));
  p.position.kv_per_s = Vec3<S>(S(4.5), S(4.5), S(6));
  p.position.mass_kg = mass_kg;
  p.position.gravity_m_s2 = gravity_m_s2;
  p.position.max_tilt_rad = S(35.0 * EIGEN_PI / 180.0);
  p.position.min_collective_thrust_n = S(0.1) * mass_kg * gravity_m_s2;
  p.position.max_collective_thrust_n = S(0.9) * S(4) * p.mixer.max_thrust_per_rotor_n;

  p.attitude.k_r_per_s = Vec3<S>(S(7), S(7), S(4));
  p.attitude.k_p_nm_s = rate_bandwidth_rad_s * inertia_kg_m2;
  p.attitude.k_d_nm_s2 = rotor_lag_s * p.attitude.k_p_nm_s;
  p.attitude.k_i_nm = S(2.5) * p.attitude.k_p_nm_s;
  p.attitude.max_rate_rad_s = Vec3<S>(S(5), S(5), S(2));
  p.attitude.integral_limit_rad = Vec3<S>(S(0.5), S(0.5), S(0.3));
  p.attitude.derivative_cutoff_hz = S(30);
  p.attitude.inertia_kg_m2 = inertia_kg_m2;

  p.estimator = EstimatorGainsWithPoles<S>(S(0.9));
  p.estimator.gravity_m_s2 = gravity_m_s2;
  return p;
}

template <typename S>
struct FlightControllerState {
  EstimatorState<S> estimator;
  AdmittanceState<S> admittance;
  AttitudeState<S> attitude;
  HalfYawTrig<S> yaw_trig;  // the reference yaw's half-angle trig, redone only when the yaw moves
};

template <typename S>
struct FlightControllerOutput {
  std::array<S, 4> rotor_thrust_n = {S(0), S(0), S(0), S(0)};
  bool armed = false;
  Reference<S> desired;  // the reference after the admittance
  S collective_thrust_n = S(0);
  Quat<S> attitude_desired = Quat<S>::Identity();
  Vec3<S> torque_body_nm = Vec3<S>::Zero();
};

template <typename S>
class FlightController {
 public:
  explicit FlightController(const FlightControllerParams<S>& params)
      : params_(params),
        max_tilt_tangent_(MaxTiltTangent(params.position)),
        mixer_constants_(MixerConstantsOf(params.mixer)) {}

  const FlightControllerParams<S>& params() const { return params_; }

  void OnImu(FlightControllerState<S>& state, const Vec3<S>& gyro_rad_s, const Vec3<S>& accel_m_s2,
             std::int64_t time_ns) const {
    PropagateImu(params_.estimator, state.estimator, gyro_rad_s, accel_m_s2, time_ns);
  }

  void OnVio(FlightControllerState<S>& state, const Vec3<S>& position_m, const Quat<S>& orientation,
             std::int64_t capture_time_ns) const {
    CorrectWithVio(params_.estimator, state.estimator, position_m, orientation, capture_time_ns);
  }

  // One control step, written into `out` (every field, so a caller can keep one output between
  // steps instead of building and copying one per step). Until the estimator is initialized the
  // output is disarmed (all rotors 0) and the controller states are held at rest, so arming starts
  // without a wound-up integrator or a stale admittance offset.
  void Step(FlightControllerState<S>& state, const Reference<S>& reference,
            const Vec3<S>& external_force_world_n, S dt_s, FlightControllerOutput<S>& out) const {
    const EstimatorState<S>& est = state.estimator;
    if (!est.initialized) {
      state.admittance = AdmittanceState<S>{};
      state.attitude = AttitudeState<S>{};
      out = FlightControllerOutput<S>{};
      out.desired = reference;
      return;
    }
    out.armed = true;
    // A broken reference must not steer the vehicle anywhere: hold the current estimate instead.
    const bool force_finite =
        AllFinite(reference)
            ? StepAdmittanceInto<S>(params_.admittance, state.admittance, reference,
                                    external_force_world_n, dt_s, out.desired)
            : StepAdmittanceInto<S>(params_.admittance, state.admittance, HoldHere(est),
                                    external_force_world_n, dt_s, out.desired);
    // The admittance checked the force; a non-finite one feeds nothing forward.
    const Vec3<S> feedforward_n =
        params_.load_feedforward && force_finite ? external_force_world_n : Vec3<S>::Zero();
    const PositionCommand<S> command = ComputePositionCommandWithTiltTangent(
        params_.position, max_tilt_tangent_, state.yaw_trig, out.desired, est.position_m,
        est.velocity_m_s, est.orientation, feedforward_n);
    out.collective_thrust_n = command.collective_thrust_n;
    out.attitude_desired = command.attitude_desired;
    out.torque_body_nm = StepAttitude(params_.attitude, state.attitude, command.attitude_desired,
                                      est.orientation, est.angular_velocity_rad_s, dt_s);
    MixInto<S>(mixer_constants_, out.collective_thrust_n, out.torque_body_nm, out.rotor_thrust_n);
  }

  // The step above, returning a fresh output.
  FlightControllerOutput<S> Step(FlightControllerState<S>& state, const Reference<S>& reference,
                                 const Vec3<S>& external_force_world_n, S dt_s) const {
    FlightControllerOutput<S> out;
    Step(state, reference, external_force_world_n, dt_s, out);
    return out;
  }

 private:
  static Reference<S> HoldHere(const EstimatorState<S>& est) {
    Reference<S> hold;
    hold.position_m = est.position_m;
    hold.yaw_rad = YawRad<S>(est.orientation);
    return hold;
  }

  FlightControllerParams<S> params_;
  S max_tilt_tangent_;                 // MaxTiltTangent(params_.position), once instead of per step
  MixerConstants<S> mixer_constants_;  // MixerConstantsOf(params_.mixer), likewise
};

}  // namespace hilrig::dut_fw
