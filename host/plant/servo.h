// The gripper's actuator: a hobby servo with its own position loop, driving the frame angle. The
// servo produces torque clamp(K (command - angle), -stall, +stall) and the grasp loads it with a
// torque that opposes closing. Because the contact behind that load is far faster than the servo
// (quasi-static, see grasp_contact.h), the servo is modelled as moving toward the unique angle
// where its torque equals the load torque: a first-order approach with the loop's time constant
// (exact exponential over the step), limited to the no-load slew rate and clamped to the travel.
// Nothing stiff is integrated, so a stiff object cannot make the step unstable; the equilibrium is
// found by a bracketed, safeguarded Newton iteration warm-started from the previous angle, with a
// fast path when nothing loads the servo between its angle and the command.
#ifndef HILRIG_HOST_PLANT_SERVO_H_
#define HILRIG_HOST_PLANT_SERVO_H_

#include "rig/result.h"

namespace hilrig::host {

// A hobby servo with its own position loop.
struct ServoParams {
  double min_angle_rad = 0.0;     // frame fully open
  double max_angle_rad = 1.6;     // frame fully closed (pads at 55 - 40 = 15 mm)
  double max_rate_rad_s = 6.0;    // no-load slew rate (~0.17 s per 60 deg)
  double stall_torque_nm = 0.25;  // largest torque the servo can hold
  double stiffness_nm_per_rad =
      5.0;                        // internal P loop: torque per rad of position error, until stall
  double time_constant_s = 0.03;  // small-signal response of the internal loop
};

struct ServoState {
  double angle_rad = 0.0;
  double rate_rad_s = 0.0;
  bool stalled = false;
};

// The load on the servo: torque opposing closing at a given angle, N m, >= 0, non-decreasing in
// the angle.
class ServoLoad {
 public:
  virtual ~ServoLoad() = default;
  virtual double TorqueAt(double angle_rad) const = 0;
  // The torque and its slope dTorque/dangle (N m/rad, >= 0). The default differentiates TorqueAt
  // numerically; loads that know the slope override this so the equilibrium search converges in
  // one or two Newton steps per tick.
  virtual double TorqueAndSlopeAt(double angle_rad, double* slope_nm_per_rad) const;
};

// Finite limits with min < max, rate, stall torque and stiffness > 0, time constant >= 0.
rig::Result<void> ValidateServo(const ServoParams& params);

// The servo's own torque at `angle_rad` for a command: clamp(K (command - angle), -stall, stall).
double ServoTorque(const ServoParams& params, double command_rad, double angle_rad);

// Angle where the servo's torque clamp(K (command - angle), -stall, +stall) equals the load
// torque, within [min, max]. The command is clamped to the travel first. If the load exceeds the
// servo's torque already at min, the answer is min (the frame rests on its open stop). A
// non-finite command returns the hint (clamped; min when the hint is not finite either).
double ServoEquilibriumAngle(const ServoParams& params, double command_rad, const ServoLoad& load,
                             double hint_rad);

// Moves toward the equilibrium: first-order with time_constant_s (exact exponential over dt),
// rate-limited to max_rate_rad_s, clamped to [min, max]. `stalled` = the equilibrium is short of
// the (clamped) command by more than 1e-3 rad because the load holds it. A non-finite command
// holds the current angle (the servo is commanded to where it is); a non-positive or non-finite
// dt, or invalid params, return the state unchanged with zero rate; a non-finite angle in the
// state is reset to min.
ServoState StepServo(const ServoParams& params, const ServoState& state, double command_rad,
                     const ServoLoad& load, double dt_s);

// The first-order approach's decay over one step, exp(-dt / time_constant) (0 for a zero time
// constant). A caller with a fixed dt computes it once and calls StepServoWithDecay, which is
// StepServo without the exp() in the tick.
double ServoLagDecay(const ServoParams& params, double dt_s);
ServoState StepServoWithDecay(const ServoParams& params, const ServoState& state,
                              double command_rad, const ServoLoad& load, double dt_s, double decay);

// A load that is zero everywhere (the frame closing on air).
class NoServoLoad final : public ServoLoad {
 public:
  double TorqueAt(double) const override { return 0.0; }
  double TorqueAndSlopeAt(double, double* slope_nm_per_rad) const override {
    *slope_nm_per_rad = 0.0;
    return 0.0;
  }
};

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_SERVO_H_
