#include "host/plant/rigid_body.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

// Quaternion kept as raw (x, y, z, w) coefficients inside the Runge-Kutta methods so that
// intermediate stages can be scaled and added without Eigen's unit-quaternion semantics getting in
// the way.
using QuatCoeffs = Eigen::Vector4d;

// dq/dt = 1/2 q ⊗ (0, w) with w in the body frame.
inline QuatCoeffs QuatDerivative(const QuatCoeffs& q, const Eigen::Vector3d& w) {
  const Eigen::Vector3d v = q.head<3>();
  const double s = q.w();
  QuatCoeffs dq;
  dq.head<3>() = 0.5 * (s * w + v.cross(w));
  dq.w() = -0.5 * v.dot(w);
  return dq;
}

// Euler's equations: I dw/dt = tau - w x (I w).
inline Eigen::Vector3d AngularAcceleration(const Eigen::Vector3d& inertia,
                                           const Eigen::Vector3d& inv_inertia,
                                           const Eigen::Vector3d& torque,
                                           const Eigen::Vector3d& w) {
  return inv_inertia.cwiseProduct(torque - w.cross(inertia.cwiseProduct(w)));
}

// The implicit rate update of semi-implicit Euler stops once the error it leaves is estimated
// below this fraction of the rate (a few ulp), so a torque-free body keeps its energy however many
// steps it takes. A fixed-point iteration that contracts less than tenfold per iteration hands over
// to Newton; the iteration cap only ends the loops on non-finite input.
constexpr double kRateTolerance = 4e-15;
constexpr double kRateMaxContraction = 0.1;
constexpr int kRateIterations = 20;

// [a]x: the matrix of a x (.).
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// Exact rotation for a constant body rate over dt, used by the semi-implicit integrator.
inline Eigen::Quaterniond DeltaRotation(const Eigen::Vector3d& w, double dt) {
  const Eigen::Vector3d half_angle = 0.5 * dt * w;
  const double theta_sq = half_angle.squaredNorm();
  double c = 0.0;  // cos(theta)
  double k = 0.0;  // sin(theta) / theta
  if (theta_sq < 1e-3) {
    // Below |theta| ~ 0.032 rad (body rates under ~63 rad/s at a 1 ms step: every step in
    // flight) the Taylor series, cut where the remainder (theta^8 / 8!, theta^8 / 9!) is below
    // double rounding, give cos and sin/theta to within an ulp without the libm sincos call and
    // the sqrt, and without 0/0 at rest.
    c = 1.0 - theta_sq * (1.0 / 2.0 - theta_sq * (1.0 / 24.0 - theta_sq * (1.0 / 720.0)));
    k = 1.0 - theta_sq * (1.0 / 6.0 - theta_sq * (1.0 / 120.0 - theta_sq * (1.0 / 5040.0)));
  } else {
    const double theta = std::sqrt(theta_sq);
    c = std::cos(theta);
    k = std::sin(theta) / theta;
  }
  return Eigen::Quaterniond(c, k * half_angle.x(), k * half_angle.y(), k * half_angle.z());
}

// The whole body state as one vector for the Runge-Kutta methods: position, velocity,
// quaternion coefficients (x, y, z, w), body rate. Fixed size, so no stage allocates.
using StateVector = Eigen::Matrix<double, 13, 1>;
constexpr int kPos = 0;
constexpr int kVel = 3;
constexpr int kQuat = 6;
constexpr int kRate = 10;

StateVector Pack(const RigidBodyState& state) {
  StateVector y;
  y.segment<3>(kPos) = state.position_m;
  y.segment<3>(kVel) = state.velocity_m_s;
  y.segment<4>(kQuat) = state.orientation.coeffs();
  y.segment<3>(kRate) = state.angular_velocity_rad_s;
  return y;
}

// The rotational half of the state: quaternion coefficients (x, y, z, w) and body rate.
using AttitudeVector = Eigen::Matrix<double, 7, 1>;

AttitudeVector PackAttitude(const RigidBodyState& state) {
  AttitudeVector y;
  y.head<4>() = state.orientation.coeffs();
  y.tail<3>() = state.angular_velocity_rad_s;
  return y;
}

RigidBodyState Unpack(const StateVector& y) {
  RigidBodyState state;
  state.position_m = y.segment<3>(kPos);
  state.velocity_m_s = y.segment<3>(kVel);
  state.orientation.coeffs() = y.segment<4>(kQuat);
  state.angular_velocity_rad_s = y.segment<3>(kRate);
  // Keeps R_WB a rotation; the drift per step is O(h^5) but accumulates over hours otherwise.
  state.orientation.normalize();
  return state;
}

// The right-hand side for one step: everything held over the step is computed once here.
class Dynamics {
 public:
  Dynamics(const RigidBodyParams& params, const Wrench& wrench, double gravity_m_s2)
      : inertia_(params.inertia_kg_m2),
        inv_inertia_(params.inertia_kg_m2.cwiseInverse()),
        torque_(wrench.torque_body_nm),
        held_accel_(wrench.force_world_n / params.mass_kg +
                    Eigen::Vector3d(0.0, 0.0, -gravity_m_s2)),
        anchor_(wrench.spring_anchor_world_m),
        stiffness_per_kg_(wrench.spring_stiffness_n_per_m / params.mass_kg),
        damping_per_kg_(wrench.spring_damping_n_s_per_m / params.mass_kg),
        has_spring_(wrench.spring_stiffness_n_per_m != 0.0 ||
                    wrench.spring_damping_n_s_per_m != 0.0) {}

  // Without the spring the acceleration is constant over the step and the translation has a
  // closed form, which every method but semi-implicit Euler reproduces exactly.
  bool translation_exact() const { return !has_spring_; }
  const Eigen::Vector3d& held_accel() const { return held_accel_; }

  Eigen::Vector3d LinearAcceleration(const Eigen::Vector3d& p, const Eigen::Vector3d& v) const {
    if (!has_spring_) return held_accel_;
    return held_accel_ - stiffness_per_kg_ * (p - anchor_) - damping_per_kg_ * v;
  }

  Eigen::Vector3d AngularAccel(const Eigen::Vector3d& w) const {
    return AngularAcceleration(inertia_, inv_inertia_, torque_, w);
  }

  // The body rate after h by the implicit midpoint rule on Euler's equations,
  //   I (w1 - w0) = h (tau - wm x I wm),  wm = (w0 + w1) / 2.
  // Without torque it keeps the rotational energy w.I w / 2 and |I w| (the angular momentum's
  // magnitude) exactly, up to the solve's tolerance: dotting the rule with wm and with I wm cancels
  // the gyroscopic term, which is what the explicit update lacks (it gains energy every step).
  //
  // Solved from the explicit step by the fixed-point iteration w1 = w0 + h dw/dt(wm): it contracts
  // by about h |w| |I_i - I_j| / I_k per iteration, 1e-5 in hover at 4 kHz, so one or two
  // iterations of one derivative each reach rounding. Where the body turns too fast for that (a
  // correction that shrinks less than tenfold) the solve restarts with Newton on the Jacobian
  // I + h/2 ([wm]x I - [I wm]x), which converges at any rate the step can resolve.
  Eigen::Vector3d ImplicitMidpointRate(const Eigen::Vector3d& w0, double h) const {
    const Eigen::Vector3d guess = w0 + AngularAccel(w0) * h;
    const double enough = kRateTolerance * guess.cwiseAbs().maxCoeff();
    double last_correction = (guess - w0).cwiseAbs().maxCoeff();
    Eigen::Vector3d w1 = guess;
    for (int iteration = 0; iteration < kRateIterations; ++iteration) {
      const Eigen::Vector3d next = w0 + AngularAccel(0.5 * (w0 + w1)) * h;
      const double correction = (next - w1).cwiseAbs().maxCoeff();
      w1 = next;
      if (!(correction > enough)) return w1;
      // The observed contraction theta bounds the error left at theta / (1 - theta) times the
      // last correction (Hairer and Wanner, Solving ODEs II, IV.8).
      const double contraction = correction / last_correction;
      if (!(contraction < kRateMaxContraction)) break;
      if (!(contraction * correction > (1.0 - contraction) * enough)) return w1;
      last_correction = correction;
    }
    return NewtonRate(w0, guess, h);
  }

  // The same rule by Newton from `guess`.
  Eigen::Vector3d NewtonRate(const Eigen::Vector3d& w0, const Eigen::Vector3d& guess,
                             double h) const {
    Eigen::Vector3d w1 = guess;
    for (int iteration = 0; iteration < kRateIterations; ++iteration) {
      const Eigen::Vector3d wm = 0.5 * (w0 + w1);
      const Eigen::Vector3d momentum = inertia_.cwiseProduct(wm);
      const Eigen::Vector3d residual =
          inertia_.cwiseProduct(w1 - w0) + h * (wm.cross(momentum) - torque_);
      const Eigen::Matrix3d jacobian =
          Eigen::Matrix3d(inertia_.asDiagonal()) +
          (0.5 * h) * (Skew(wm) * inertia_.asDiagonal() - Skew(momentum));
      const Eigen::Vector3d correction = jacobian.inverse() * residual;
      w1 -= correction;
      if (!(correction.cwiseAbs().maxCoeff() > kRateTolerance * w1.cwiseAbs().maxCoeff())) break;
    }
    return w1;
  }

  // The attitude's share of Derivative: it never depends on the translation.
  AttitudeVector AttitudeDerivative(const AttitudeVector& y) const {
    AttitudeVector dy;
    dy.head<4>() = QuatDerivative(y.head<4>(), y.tail<3>());
    dy.tail<3>() = AngularAccel(y.tail<3>());
    return dy;
  }

  StateVector Derivative(const StateVector& y) const {
    StateVector dy;
    dy.segment<3>(kPos) = y.segment<3>(kVel);
    dy.segment<3>(kVel) = LinearAcceleration(y.segment<3>(kPos), y.segment<3>(kVel));
    dy.segment<4>(kQuat) = QuatDerivative(y.segment<4>(kQuat), y.segment<3>(kRate));
    dy.segment<3>(kRate) = AngularAccel(y.segment<3>(kRate));
    return dy;
  }

 private:
  Eigen::Vector3d inertia_;
  Eigen::Vector3d inv_inertia_;
  Eigen::Vector3d torque_;
  Eigen::Vector3d held_accel_;
  Eigen::Vector3d anchor_;
  double stiffness_per_kg_;
  double damping_per_kg_;
  bool has_spring_;
};

// Overwrites the translation with the closed form when the acceleration is constant, so the
// Runge-Kutta methods do not add round-off to an exact answer.
void ApplyExactTranslation(const Dynamics& dynamics, const RigidBodyState& start, double h,
                           RigidBodyState& next) {
  if (!dynamics.translation_exact()) return;
  const Eigen::Vector3d& accel = dynamics.held_accel();
  next.position_m = start.position_m + start.velocity_m_s * h + 0.5 * accel * h * h;
  next.velocity_m_s = start.velocity_m_s + accel * h;
}

RigidBodyState SemiImplicitEulerStep(const Dynamics& dynamics, const RigidBodyState& state,
                                     double h) {
  RigidBodyState next;
  next.velocity_m_s =
      state.velocity_m_s + dynamics.LinearAcceleration(state.position_m, state.velocity_m_s) * h;
  next.position_m = state.position_m + next.velocity_m_s * h;
  // The rotation uses the step's mean rate, the same one the rate update balanced: the world
  // angular momentum of a torque-free body then errs by O(h^2) instead of O(h), and the rotational
  // half of the step is symmetric in time.
  next.angular_velocity_rad_s = dynamics.ImplicitMidpointRate(state.angular_velocity_rad_s, h);
  const Eigen::Vector3d mean_rate =
      0.5 * (state.angular_velocity_rad_s + next.angular_velocity_rad_s);
  next.orientation = state.orientation * DeltaRotation(mean_rate, h);
  next.orientation.normalize();
  return next;
}

// The closed-form translation plus the integrated attitude, renormalized as Unpack does.
RigidBodyState WithAttitude(const Dynamics& dynamics, const RigidBodyState& start, double h,
                            const AttitudeVector& y) {
  RigidBodyState next;
  next.orientation.coeffs() = y.head<4>();
  next.angular_velocity_rad_s = y.tail<3>();
  next.orientation.normalize();
  ApplyExactTranslation(dynamics, start, h, next);
  return next;
}

enum class FixedStepMethod { kMidpoint, kRk4 };

// One step of the midpoint rule or classic RK4 on any state vector, `f` its derivative.
template <typename Vector, typename Derivative>
Vector FixedStepOf(FixedStepMethod method, const Vector& y0, double h, const Derivative& f) {
  const Vector k1 = f(y0);
  const Vector k2 = f(y0 + 0.5 * h * k1);
  if (method == FixedStepMethod::kMidpoint) return y0 + h * k2;
  const Vector k3 = f(y0 + 0.5 * h * k2);
  const Vector k4 = f(y0 + h * k3);
  return y0 + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

// A fixed-step method on the body. With the translation in closed form only the seven attitude
// numbers are integrated: element for element the same arithmetic as on the full vector, so the
// result is bit-identical at about half the cost.
RigidBodyState FixedStep(const Dynamics& dynamics, const RigidBodyState& state, double h,
                         FixedStepMethod method) {
  if (dynamics.translation_exact()) {
    const auto attitude = [&dynamics](const AttitudeVector& y) {
      return dynamics.AttitudeDerivative(y);
    };
    return WithAttitude(dynamics, state, h, FixedStepOf(method, PackAttitude(state), h, attitude));
  }
  const auto full = [&dynamics](const StateVector& y) { return dynamics.Derivative(y); };
  return Unpack(FixedStepOf(method, Pack(state), h, full));
}

// Dormand & Prince (1980), "A family of embedded Runge-Kutta formulae", RK5(4)7M. The fifth-order
// solution propagates; the difference to the embedded fourth-order one estimates the error.
namespace dp {
constexpr double a21 = 1.0 / 5.0;
constexpr double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
constexpr double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
constexpr double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                 a54 = -212.0 / 729.0;
constexpr double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                 a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
// Fifth-order weights; they are also the last stage's row, which makes the method FSAL.
constexpr double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0, b5 = -2187.0 / 6784.0,
                 b6 = 11.0 / 84.0;
// Fifth minus fourth-order weights.
constexpr double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                 e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
}  // namespace dp

// Largest per-component error relative to its allowance; <= 1 accepts the substep.
double ScaledError(const StateVector& error, const StateVector& y0, const StateVector& y1,
                   double tolerance) {
  const StateVector scale =
      (y0.cwiseAbs().cwiseMax(y1.cwiseAbs()).array() * tolerance + tolerance).matrix();
  const double worst = error.cwiseQuotient(scale).cwiseAbs().maxCoeff();
  return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
}

double StepFactor(const RigidBodyIntegratorOptions& options, double error, bool after_reject) {
  const double max_growth = after_reject ? 1.0 : options.max_growth;
  if (error == 0.0) return max_growth;
  const double proposed = options.safety_factor * std::pow(error, -0.2);
  return std::clamp(proposed, options.min_growth, max_growth);
}

RigidBodyState NotFinite() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  RigidBodyState state;
  state.position_m.setConstant(nan);
  state.velocity_m_s.setConstant(nan);
  state.orientation.coeffs().setConstant(nan);
  state.angular_velocity_rad_s.setConstant(nan);
  return state;
}

RigidBodyState DormandPrinceStep(const Dynamics& dynamics, const RigidBodyState& state, double dt,
                                 const RigidBodyIntegratorOptions& options,
                                 IntegratorStats& stats) {
  using namespace dp;
  StateVector y = Pack(state);
  StateVector k1 = dynamics.Derivative(y);
  double t = 0.0;
  double h = dt;  // try the whole step first: in smooth flight it is accepted at once
  bool after_reject = false;
  while (t < dt) {
    if (stats.accepted_substeps + stats.rejected_substeps >= options.max_substeps) {
      stats.failed = true;
      return NotFinite();
    }
    const bool last = h >= dt - t;
    if (last) h = dt - t;
    if (t + h == t) {  // the step size underflowed: the motion cannot be resolved
      stats.failed = true;
      return NotFinite();
    }
    const StateVector k2 = dynamics.Derivative(y + h * (a21 * k1));
    const StateVector k3 = dynamics.Derivative(y + h * (a31 * k1 + a32 * k2));
    const StateVector k4 = dynamics.Derivative(y + h * (a41 * k1 + a42 * k2 + a43 * k3));
    const StateVector k5 = dynamics.Derivative(y + h * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4));
    const StateVector k6 =
        dynamics.Derivative(y + h * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5));
    StateVector y1 = y + h * (b1 * k1 + b3 * k3 + b4 * k4 + b5 * k5 + b6 * k6);
    const StateVector k7 = dynamics.Derivative(y1);
    const StateVector error = h * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7);
    const double scaled = ScaledError(error, y, y1, options.tolerance);
    const double factor = StepFactor(options, scaled, after_reject);
    if (scaled <= 1.0) {
      ++stats.accepted_substeps;
      y1.segment<4>(kQuat).normalize();
      y = y1;
      k1 = k7;  // first same as last
      t = last ? dt : t + h;
      after_reject = false;
    } else {
      ++stats.rejected_substeps;
      after_reject = true;
    }
    h *= factor;
  }
  RigidBodyState next = Unpack(y);
  ApplyExactTranslation(dynamics, state, dt, next);
  return next;
}

bool UsableOptions(const RigidBodyIntegratorOptions& options) {
  return options.tolerance > 0.0 && options.tolerance < 1.0 && options.safety_factor > 0.0 &&
         options.safety_factor <= 1.0 && options.min_growth > 0.0 && options.min_growth < 1.0 &&
         options.max_growth > 1.0 && std::isfinite(options.max_growth) && options.max_substeps > 0;
}

}  // namespace

RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator) {
  return StepRigidBody(params, state, wrench, gravity_m_s2, dt_s, integrator,
                       RigidBodyIntegratorOptions{});
}

RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator, const RigidBodyIntegratorOptions& options,
                             IntegratorStats* stats) {
  IntegratorStats local;
  IntegratorStats& out = stats != nullptr ? *stats : local;
  out = IntegratorStats{};
  const bool adaptive = integrator == Integrator::kDormandPrince;
  if (!(dt_s > 0.0) || !std::isfinite(dt_s) || (adaptive && !UsableOptions(options))) {
    out.failed = true;
    return state;
  }
  const Dynamics dynamics(params, wrench, gravity_m_s2);
  switch (integrator) {
    case Integrator::kSemiImplicitEuler:
      out.accepted_substeps = 1;
      return SemiImplicitEulerStep(dynamics, state, dt_s);
    case Integrator::kMidpoint:
      out.accepted_substeps = 1;
      return FixedStep(dynamics, state, dt_s, FixedStepMethod::kMidpoint);
    case Integrator::kDormandPrince:
      return DormandPrinceStep(dynamics, state, dt_s, options, out);
    case Integrator::kRk4:
      break;
  }
  out.accepted_substeps = 1;
  return FixedStep(dynamics, state, dt_s, FixedStepMethod::kRk4);
}

const char* IntegratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::kSemiImplicitEuler:
      return "semi-implicit Euler";
    case Integrator::kMidpoint:
      return "midpoint RK2";
    case Integrator::kDormandPrince:
      return "Dormand-Prince RK5(4)";
    case Integrator::kRk4:
      break;
  }
  return "RK4";
}

double MechanicalEnergy(const RigidBodyParams& params, const RigidBodyState& state,
                        double gravity_m_s2) {
  const Eigen::Vector3d& w = state.angular_velocity_rad_s;
  const double translational = 0.5 * params.mass_kg * state.velocity_m_s.squaredNorm();
  const double rotational = 0.5 * w.dot(params.inertia_kg_m2.cwiseProduct(w));
  const double potential = params.mass_kg * gravity_m_s2 * state.position_m.z();
  return translational + rotational + potential;
}

Eigen::Vector3d AngularMomentumWorld(const RigidBodyParams& params, const RigidBodyState& state) {
  return state.orientation * params.inertia_kg_m2.cwiseProduct(state.angular_velocity_rad_s);
}

}  // namespace hilrig::host
