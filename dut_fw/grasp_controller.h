// Grasp force controller of the servo that shrinks the frame (docs/design.md section 1): an
// admittance on the servo angle driven by the grasp-force error, so the frame closes until the pads
// feel the desired squeeze and then holds it, whatever the object's size and stiffness:
//
//   M_θ Δθ̈ + B_θ Δθ̇ + K_θ Δθ = f_d − f̂_g,   θ_d = clamp(θ_r + Δθ, open, closed)
//
// with f̂_g = Σ_i |f̂_i · n̂_i| (tactile_processor.h) and θ_r the angle where the mission expects
// first contact. Integration is semi-implicit Euler as in admittance.h, so the same discrete bound
// holds: with c = B/M, k = K/M, dt < (√(c² + 4k) − c) / k (2/c for K = 0); MaxStableGraspDt().
//
// Default tuning. The loop gain is the grasp's stiffness seen through the servo,
// k_g = dF_g/dθ = 6 pads × k_contact × 0.025 m/rad: ≈ 75 N/rad for a balloon (550 N/m in series
// with the 5.6 N/mm pad) and ≈ 6 × 5600 × 0.025 = 840 N/rad for a rigid object, where the pads
// alone give. With K_θ = 0 the open loop is k_g e^(−sT) / (s (M s + B) (τ s + 1)): an integrator,
// so the force error has no steady state, crossing over at ω_c ≈ k_g / B. The force arrives at
// 50 Hz (zero-order hold, ~10 ms of mean delay) and the servo lags by τ ≈ 30 ms, ≈ 40–50 ms of
// delay in all, so ω_c must stay well below 1 / delay ≈ 20 rad/s for the stiffest object, while
// the softest must still settle in a few seconds:
//  - B_θ = 65 N·s/rad: balloon ω_c = 1.15 rad/s (time constant 0.87 s, within 1 % after 4 s);
//    rigid ω_c = 12.9 rad/s with a phase margin of 90° − 21° (servo) − 7° (hold) − 2° (M) ≈ 59°,
//    still ≈ 52° with another 10 ms of transport delay (simulated overshoot 6 % and 12 %;
//    a balloon bursts on overshoot, so this margin is the point of the damping).
//  - M_θ = 0.2 N·s²/rad: the mechanical pole B/M = 325 rad/s sits 25× above the fastest
//    crossover, so it costs only 2° of phase, and the discrete bound 2M/B = 6.2 ms (5.9 ms with a
//    rigid object's 840 N/rad in the loop) leaves a 6× margin over the 1 ms control step.
//  - K_θ = 0: the force error integrates, so the grasp force has no steady-state error.
// A new grasp starts with the servo wherever the last command left it (fully open, typically), and
// it needs ~0.2 s to travel to θ_r. Integrating the force error during that travel would wind Δθ up
// against a force that cannot appear yet (9 mrad/s × 0.2 s ≈ 1.8 mrad: 1.5 N on a rigid object,
// 2.5× the usual f_d), so Δθ is held at 0 for the travel time |θ_r − θ_prev| / servo_max_rate +
// servo_settle_s (≈ 3 servo time constants), or until the measured force already reaches f_d.
// The admittance is a force regulator, not an approach planner: with no contact it closes at the
// terminal rate f_d / B (9 mrad/s for 0.6 N), so θ_r should be at, or just short of, the expected
// contact angle (that is what it is for): each mrad short costs 0.1 s at 0.6 N, and each mrad past
// squeezes a rigid object with k_g × 1 mrad = 0.84 N at once. A scenario may override the gains.
//
// Robustness, because a bad sample must never squeeze harder: an invalid (not zeroed or stale) or
// non-finite force estimate, a non-finite f_d, θ_r or dt, or dt <= 0 holds Δθ and its rate and is
// counted in rejected_inputs; a non-finite θ_r additionally holds the previous command. A negative
// f_d asks for no squeeze and is regulated as zero. Anti-windup at the servo's limits clamps Δθ
// with the command and zeroes a rate that pushes further out, so a missing object leaves the
// command at the closed limit and force brings it back on the first step that sees it. Invalid
// parameters (GraspParamsValid false) never regulate: the servo is commanded to the open angle
// (or held where it was if even that is non-finite). The output is never NaN.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

enum class GraspMode : std::uint8_t { kOpen = 0, kForce = 1 };

template <typename S>
struct GraspCommand {
  GraspMode mode = GraspMode::kOpen;
  S force_n = S(0);              // f_d, N: desired sum over the pads of the normal force
  S reference_angle_rad = S(0);  // θ_r: expected first contact (e.g. from the object's size)
};

template <typename S>
struct GraspAdmittanceParams {
  S mass = S(0.2);                // M_θ, N·s²/rad, > 0
  S damping = S(65);              // B_θ, N·s/rad, >= 0
  S stiffness = S(0);             // K_θ, N/rad, >= 0; 0 = force error integrates (no steady error)
  S open_angle_rad = S(0);        // servo angle that fully opens the frame
  S closed_angle_rad = S(1.6);    // servo angle that fully closes it; range is [open, closed]
  bool force_feedback = true;     // false = the ablation: the servo closes open-loop to closed
  S servo_max_rate_rad_s = S(6);  // servo no-load slew (0.17 s per 60°), > 0; ∞ = no travel hold
  S servo_settle_s = S(0.1);      // ≈ 3 servo time constants, >= 0
};

template <typename S>
struct GraspControllerState {
  S offset_rad = S(0);  // Δθ
  S offset_rate_rad_s = S(0);
  GraspMode last_mode = GraspMode::kOpen;
  S last_command_rad = S(0);  // θ_d of the previous step, held when θ_r is unusable
  S travel_hold_s = S(0);     // time left before Δθ integrates in a new grasp (servo travel)
  std::uint32_t rejected_inputs = 0;  // steps whose estimate, command, dt or params were unusable
};

template <typename S>
struct GraspOutput {
  S servo_angle_rad = S(0);  // θ_d, the servo command
  S force_error_n = S(0);    // f_d − f̂_g used this step (0 when not regulating)
  bool regulating = false;
};

// A start-up check for the integrator, and the gate of every checked step: finite gains, M > 0, B,
// K >= 0, a non-empty servo range with closed above open (Δθ > 0 must close the frame, or the force
// feedback would have the wrong sign), a positive slew rate and a finite settle time >= 0.
template <typename S>
bool GraspParamsValid(const GraspAdmittanceParams<S>& params) {
  return std::isfinite(params.mass) && std::isfinite(params.damping) &&
         std::isfinite(params.stiffness) && std::isfinite(params.open_angle_rad) &&
         std::isfinite(params.closed_angle_rad) && params.mass > S(0) && params.damping >= S(0) &&
         params.stiffness >= S(0) && params.closed_angle_rad > params.open_angle_rad &&
         params.servo_max_rate_rad_s > S(0) && std::isfinite(params.servo_settle_s) &&
         params.servo_settle_s >= S(0);
}

// Largest dt (s) for which the semi-implicit Euler update of the admittance alone is stable (see
// header); 0 for invalid parameters. In contact the object's k_g adds to K_θ and lowers the bound.
template <typename S>
S MaxStableGraspDt(const GraspAdmittanceParams<S>& params) {
  if (!GraspParamsValid(params)) return S(0);
  const S c = params.damping / params.mass;
  const S k = params.stiffness / params.mass;
  if (k > S(0)) return (std::sqrt(c * c + S(4) * k) - c) / k;
  return c > S(0) ? S(2) / c : std::numeric_limits<S>::infinity();
}

namespace grasp_controller_internal {

template <typename S>
void CountRejected(GraspControllerState<S>& state) {
  if (state.rejected_inputs < std::numeric_limits<std::uint32_t>::max()) ++state.rejected_inputs;
}

template <typename S>
GraspOutput<S> Command(GraspControllerState<S>& state, S angle_rad, S force_error_n,
                       bool regulating) {
  state.last_command_rad = angle_rad;
  return GraspOutput<S>{angle_rad, force_error_n, regulating};
}

// θ_r + Δθ within the servo's range; at a limit Δθ is pinned to it and a rate that pushes further
// out is dropped, so nothing winds up while the servo cannot follow.
template <typename S>
S ClampToRange(const GraspAdmittanceParams<S>& params, GraspControllerState<S>& state,
               S reference_angle_rad) {
  const S angle_rad = reference_angle_rad + state.offset_rad;
  if (angle_rad >= params.closed_angle_rad) {
    state.offset_rad = params.closed_angle_rad - reference_angle_rad;
    state.offset_rate_rad_s = std::min(state.offset_rate_rad_s, S(0));
    return params.closed_angle_rad;
  }
  if (angle_rad <= params.open_angle_rad) {
    state.offset_rad = params.open_angle_rad - reference_angle_rad;
    state.offset_rate_rad_s = std::max(state.offset_rate_rad_s, S(0));
    return params.open_angle_rad;
  }
  return angle_rad;
}

// How long the servo needs from `from_rad` to the new grasp's θ_r (a full stroke when θ_r is not
// a number yet, since the first usable θ_r may be anywhere in the range).
template <typename S>
S TravelTime(const GraspAdmittanceParams<S>& params, S from_rad, S reference_angle_rad) {
  const S distance_rad = std::isfinite(reference_angle_rad)
                             ? std::abs(std::clamp(reference_angle_rad, params.open_angle_rad,
                                                   params.closed_angle_rad) -
                                        from_rad)
                             : params.closed_angle_rad - params.open_angle_rad;
  return distance_rad / params.servo_max_rate_rad_s + params.servo_settle_s;
}

// No offset and no offset rate, in `mode`: a grasp that opens or starts afresh carries nothing of
// the last one's admittance.
template <typename S>
void ResetOffset(GraspControllerState<S>& state, GraspMode mode) {
  state.offset_rad = S(0);
  state.offset_rate_rad_s = S(0);
  state.last_mode = mode;
}

}  // namespace grasp_controller_internal

// StepGraspController for parameters already known to be valid. Precondition:
// GraspParamsValid(params) is true (the parameters are constant, so a caller that holds them checks
// once where it sets them, and calls StepGraspController instead when the check failed); with
// invalid parameters the result is unspecified. Every input other than the parameters is checked
// here as in StepGraspController.
template <typename S>
GraspOutput<S> StepGraspControllerWithValidParams(const GraspAdmittanceParams<S>& params,
                                                  GraspControllerState<S>& state,
                                                  const NoDeduce<GraspCommand<S>>& command,
                                                  NoDeduce<S> grasp_force_estimate_n,
                                                  NoDeduce<bool> estimate_valid, NoDeduce<S> dt_s) {
  namespace internal = grasp_controller_internal;
  const S last_command_rad = std::clamp(
      std::isfinite(state.last_command_rad) ? state.last_command_rad : params.open_angle_rad,
      params.open_angle_rad, params.closed_angle_rad);
  if (command.mode != GraspMode::kForce || !params.force_feedback) {
    // An unknown mode is a corrupted command: open is the safe reading of it (and it is counted).
    if (command.mode != GraspMode::kForce && command.mode != GraspMode::kOpen) {
      internal::CountRejected(state);
    }
    const bool squeeze = command.mode == GraspMode::kForce;
    internal::ResetOffset(state, squeeze ? GraspMode::kForce : GraspMode::kOpen);
    return internal::Command(state, squeeze ? params.closed_angle_rad : params.open_angle_rad, S(0),
                             false);
  }

  if (state.last_mode != GraspMode::kForce) {  // a new grasp starts at θ_r
    internal::ResetOffset(state, GraspMode::kForce);
    state.travel_hold_s =
        internal::TravelTime(params, last_command_rad, S(command.reference_angle_rad));
  }
  const S reference_angle_rad = command.reference_angle_rad;
  if (!std::isfinite(reference_angle_rad)) {
    internal::CountRejected(state);
    return internal::Command(state, last_command_rad, S(0), false);
  }
  // The servo travels whatever the force estimate says, so the hold runs down on any valid dt.
  const bool dt_usable = std::isfinite(dt_s) && dt_s > S(0);
  const bool travelling = state.travel_hold_s > S(0);
  if (travelling && dt_usable) state.travel_hold_s -= dt_s;
  // The difference of two finite forces can still overflow; such an error is as unusable as NaN.
  const S force_error_n = std::max(command.force_n, S(0)) - grasp_force_estimate_n;
  const bool usable = estimate_valid && std::isfinite(force_error_n) && dt_usable;
  if (!usable) {
    internal::CountRejected(state);
    return internal::Command(state, internal::ClampToRange(params, state, reference_angle_rad),
                             S(0), false);
  }

  if (travelling && force_error_n > S(0)) {  // servo still on its way to θ_r
    return internal::Command(state, internal::ClampToRange(params, state, reference_angle_rad),
                             S(0), false);
  }
  state.travel_hold_s = S(0);
  const S held_offset_rad = state.offset_rad;
  const S held_rate_rad_s = state.offset_rate_rad_s;
  const S accel_rad_s2 = (force_error_n - params.damping * state.offset_rate_rad_s -
                          params.stiffness * state.offset_rad) /
                         params.mass;
  state.offset_rate_rad_s += accel_rad_s2 * dt_s;
  state.offset_rad += state.offset_rate_rad_s * dt_s;
  const S angle_rad = internal::ClampToRange(params, state, reference_angle_rad);
  if (!std::isfinite(angle_rad) || !std::isfinite(state.offset_rad) ||
      !std::isfinite(state.offset_rate_rad_s)) {
    // Only an overflow from extreme (finite) gains or dt gets here; dropped like a bad sample.
    state.offset_rad = held_offset_rad;
    state.offset_rate_rad_s = held_rate_rad_s;
    internal::CountRejected(state);
    return internal::Command(state, last_command_rad, S(0), false);
  }
  return internal::Command(state, angle_rad, force_error_n, true);
}

// One control step of the servo command (see header for the modes and the rejected inputs), with
// the parameters checked first: invalid ones never regulate and are counted in rejected_inputs.
template <typename S>
GraspOutput<S> StepGraspController(const GraspAdmittanceParams<S>& params,
                                   GraspControllerState<S>& state,
                                   const NoDeduce<GraspCommand<S>>& command,
                                   NoDeduce<S> grasp_force_estimate_n,
                                   NoDeduce<bool> estimate_valid, NoDeduce<S> dt_s) {
  namespace internal = grasp_controller_internal;
  if (!GraspParamsValid(params)) {
    internal::CountRejected(state);
    internal::ResetOffset(state, GraspMode::kOpen);
    const S angle_rad = std::isfinite(params.open_angle_rad)    ? params.open_angle_rad
                        : std::isfinite(state.last_command_rad) ? state.last_command_rad
                                                                : S(0);
    return internal::Command(state, angle_rad, S(0), false);
  }
  return StepGraspControllerWithValidParams<S>(params, state, command, grasp_force_estimate_n,
                                               estimate_valid, dt_s);
}

}  // namespace hilrig::dut_fw
