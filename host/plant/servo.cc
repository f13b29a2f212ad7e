#include "host/plant/servo.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace hilrig::host {
namespace {

// Bracket width (rad) below which the equilibrium is considered found; far below anything the
// frame geometry or the DUT can resolve.
constexpr double kAngleTolerance = 1e-12;
// Newton steps allowed before the search falls back to plain bisection, so a kinked load (contact
// onset, torque saturation) cannot make it cycle.
constexpr int kNewtonTries = 12;
constexpr int kMaxIterations = 100;
constexpr double kStallMargin = 1e-3;

bool Usable(const ServoParams& p) {
  return std::isfinite(p.min_angle_rad) && std::isfinite(p.max_angle_rad) &&
         p.min_angle_rad < p.max_angle_rad && std::isfinite(p.max_rate_rad_s) &&
         p.max_rate_rad_s > 0 && std::isfinite(p.stall_torque_nm) && p.stall_torque_nm > 0 &&
         std::isfinite(p.stiffness_nm_per_rad) && p.stiffness_nm_per_rad > 0 &&
         std::isfinite(p.time_constant_s) && p.time_constant_s >= 0;
}

rig::Result<void> FieldError(const char* field, const char* problem) {
  return rig::MakeError(std::string("servo: ") + field + ": " + problem);
}

double Clamp(const ServoParams& p, double angle_rad) {
  return std::clamp(angle_rad, p.min_angle_rad, p.max_angle_rad);
}

// Slope of the servo's torque with respect to the angle: -K inside the linear band, 0 saturated.
double ServoTorqueSlope(const ServoParams& p, double command_rad, double angle_rad) {
  const double torque = p.stiffness_nm_per_rad * (command_rad - angle_rad);
  return std::abs(torque) < p.stall_torque_nm ? -p.stiffness_nm_per_rad : 0.0;
}

}  // namespace

double ServoLoad::TorqueAndSlopeAt(double angle_rad, double* slope_nm_per_rad) const {
  constexpr double kStep = 1e-7;
  const double torque = TorqueAt(angle_rad);
  const double slope = (TorqueAt(angle_rad + kStep) - torque) / kStep;
  *slope_nm_per_rad = std::isfinite(slope) ? std::max(0.0, slope) : 0.0;
  return torque;
}

rig::Result<void> ValidateServo(const ServoParams& p) {
  if (!std::isfinite(p.min_angle_rad)) return FieldError("min_angle_rad", "must be finite");
  if (!std::isfinite(p.max_angle_rad) || !(p.max_angle_rad > p.min_angle_rad)) {
    return FieldError("max_angle_rad", "must be finite and > min_angle_rad");
  }
  if (!std::isfinite(p.max_rate_rad_s) || p.max_rate_rad_s <= 0) {
    return FieldError("max_rate_rad_s", "must be finite and > 0");
  }
  if (!std::isfinite(p.stall_torque_nm) || p.stall_torque_nm <= 0) {
    return FieldError("stall_torque_nm", "must be finite and > 0");
  }
  if (!std::isfinite(p.stiffness_nm_per_rad) || p.stiffness_nm_per_rad <= 0) {
    return FieldError("stiffness_nm_per_rad", "must be finite and > 0");
  }
  if (!std::isfinite(p.time_constant_s) || p.time_constant_s < 0) {
    return FieldError("time_constant_s", "must be finite and >= 0");
  }
  return {};
}

double ServoTorque(const ServoParams& p, double command_rad, double angle_rad) {
  return std::clamp(p.stiffness_nm_per_rad * (command_rad - angle_rad), -p.stall_torque_nm,
                    p.stall_torque_nm);
}

double ServoEquilibriumAngle(const ServoParams& p, double command_rad, const ServoLoad& load,
                             double hint_rad) {
  if (!std::isfinite(command_rad)) {
    return std::isfinite(hint_rad) ? Clamp(p, hint_rad) : p.min_angle_rad;
  }
  const double command = Clamp(p, command_rad);
  // residual(a) = servo torque - load is non-increasing in a and <= 0 at the command, so the
  // root lies in [min, command]. The search starts at the hint (in steady contact the previous
  // angle is the answer and one evaluation settles it) and keeps a bracket [lo, hi]; it takes
  // Newton steps while they stay inside, else a secant of the bracket ends once both are known,
  // else it evaluates an unknown end. A non-finite load counts as no load rather than leaking.
  double lo = p.min_angle_rad;
  double hi = command;
  double residual_lo = 0.0;
  double residual_hi = 0.0;
  bool lo_known = false;
  bool hi_known = false;
  double x = std::isfinite(hint_rad) ? std::clamp(hint_rad, lo, hi) : hi;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    double load_slope = 0.0;
    double load_torque = load.TorqueAndSlopeAt(x, &load_slope);
    if (!std::isfinite(load_torque) || !std::isfinite(load_slope)) {
      load_torque = 0.0;
      load_slope = 0.0;
    }
    // Nothing loads the servo at its command: being non-decreasing, the load is zero all the way
    // there, and the servo reaches the command exactly (the no-contact fast path).
    if (x == command && !(load_torque > 0)) return command;
    const double residual = ServoTorque(p, command, x) - load_torque;
    if (residual <= 0 && x == p.min_angle_rad) return x;  // the load holds it on the open stop
    if (residual == 0) return x;
    if (residual > 0) {
      lo = x;
      residual_lo = residual;
      lo_known = true;
    } else {
      hi = x;
      residual_hi = residual;
      hi_known = true;
    }
    if (hi - lo <= kAngleTolerance) return 0.5 * (lo + hi);

    const double slope = ServoTorqueSlope(p, command, x) - load_slope;
    if (iteration < kNewtonTries && slope < 0) {
      const double step = -residual / slope;
      if (std::abs(step) <= kAngleTolerance) return std::clamp(x + step, lo, hi);
      if (x + step > lo && x + step < hi) {
        x += step;
        continue;
      }
    }
    if (!hi_known) {
      x = hi;
    } else if (!lo_known) {
      x = lo;
    } else if (iteration < kNewtonTries) {
      const double secant = lo + residual_lo * (hi - lo) / (residual_lo - residual_hi);
      x = (secant > lo && secant < hi) ? secant : 0.5 * (lo + hi);
    } else {
      x = 0.5 * (lo + hi);
    }
  }
  return x;
}

double ServoLagDecay(const ServoParams& p, double dt_s) {
  return p.time_constant_s > 0 ? std::exp(-dt_s / p.time_constant_s) : 0.0;
}

ServoState StepServo(const ServoParams& p, const ServoState& state, double command_rad,
                     const ServoLoad& load, double dt_s) {
  return StepServoWithDecay(p, state, command_rad, load, dt_s, ServoLagDecay(p, dt_s));
}

ServoState StepServoWithDecay(const ServoParams& p, const ServoState& state, double command_rad,
                              const ServoLoad& load, double dt_s, double decay) {
  if (!Usable(p) || !std::isfinite(dt_s) || dt_s <= 0) {
    ServoState held = state;
    held.rate_rad_s = 0.0;
    return held;
  }
  const double angle = std::isfinite(state.angle_rad) ? Clamp(p, state.angle_rad) : p.min_angle_rad;
  const double command = Clamp(p, std::isfinite(command_rad) ? command_rad : angle);
  const double equilibrium = ServoEquilibriumAngle(p, command, load, angle);

  const double max_step = p.max_rate_rad_s * dt_s;
  const double step = std::clamp((equilibrium - angle) * (1.0 - decay), -max_step, max_step);

  ServoState next;
  next.angle_rad = Clamp(p, angle + step);
  next.rate_rad_s = (next.angle_rad - angle) / dt_s;
  next.stalled = command - equilibrium > kStallMargin;
  return next;
}

}  // namespace hilrig::host
