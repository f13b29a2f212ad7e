// Accuracy and stability of the rigid-body integrators: observed convergence orders, the
// adaptive integrator's error control, and the step sizes at which each explicit method goes
// unstable on a stiff spring (limits derived here from each method's stability function).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>

#include "host/plant/rigid_body.h"

namespace hilrig::host {
namespace {

// ---- Convergence on a smooth tumbling body ------------------------------------------------

// All principal moments distinct, a constant body torque and a soft damped spring, so that
// every part of the state (translation included) goes through the integrator's stages.
RigidBodyParams TumblingBody() {
  RigidBodyParams params;
  params.inertia_kg_m2 = {2e-3, 3e-3, 5e-3};
  return params;
}

Wrench TumblingWrench() {
  Wrench wrench;
  wrench.force_world_n = {0.2, -0.1, 5.0};
  wrench.torque_body_nm = {1e-3, -2e-3, 5e-4};
  wrench.spring_anchor_world_m = {0.0, 0.0, 1.0};
  wrench.spring_stiffness_n_per_m = 2.0;  // omega = 1.9 rad/s on 0.556 kg
  wrench.spring_damping_n_s_per_m = 0.1;
  return wrench;
}

RigidBodyState TumblingStart() {
  RigidBodyState state;
  state.velocity_m_s = {0.5, 0.0, -0.2};
  state.angular_velocity_rad_s = {3.0, -1.0, 2.0};
  return state;
}

RigidBodyState Integrate(Integrator integrator, double dt_s, double duration_s,
                         const RigidBodyIntegratorOptions& options = {},
                         std::uint64_t* accepted = nullptr) {
  const RigidBodyParams params = TumblingBody();
  const Wrench wrench = TumblingWrench();
  RigidBodyState state = TumblingStart();
  const int steps = static_cast<int>(std::lround(duration_s / dt_s));
  for (int i = 0; i < steps; ++i) {
    IntegratorStats stats;
    state = StepRigidBody(params, state, wrench, 9.81, dt_s, integrator, options, &stats);
    if (accepted != nullptr) *accepted += stats.accepted_substeps;
  }
  return state;
}

// Largest difference over all state components; q and -q are the same rotation.
double StateDistance(const RigidBodyState& a, const RigidBodyState& b) {
  const Eigen::Vector4d qa = a.orientation.coeffs();
  Eigen::Vector4d qb = b.orientation.coeffs();
  if (qa.dot(qb) < 0) qb = -qb;
  return std::max({(a.position_m - b.position_m).cwiseAbs().maxCoeff(),
                   (a.velocity_m_s - b.velocity_m_s).cwiseAbs().maxCoeff(),
                   (qa - qb).cwiseAbs().maxCoeff(),
                   (a.angular_velocity_rad_s - b.angular_velocity_rad_s).cwiseAbs().maxCoeff()});
}

// RK4 at 10 us: its error (~1e-17 by the h^4 scaling measured below) is far below anything the
// convergence tests resolve.
const RigidBodyState& Reference() {
  static const RigidBodyState reference = Integrate(Integrator::kRk4, 1e-5, 1.0);
  return reference;
}

// log2 of the error ratio for each halving of dt from dt0.
std::vector<double> ObservedOrders(Integrator integrator, double dt0_s, int halvings) {
  std::vector<double> errors;
  for (int i = 0; i <= halvings; ++i) {
    const double dt = dt0_s / std::pow(2.0, i);
    errors.push_back(StateDistance(Integrate(integrator, dt, 1.0), Reference()));
  }
  std::vector<double> orders;
  for (int i = 0; i < halvings; ++i) orders.push_back(std::log2(errors[i] / errors[i + 1]));
  return orders;
}

TEST(IntegratorConvergenceTest, ReferenceAgreesWithTightDormandPrince) {
  // Two unrelated methods on the same equations: guards the reference itself.
  RigidBodyIntegratorOptions tight;
  tight.tolerance = 1e-12;
  const RigidBodyState dp = Integrate(Integrator::kDormandPrince, 0.05, 1.0, tight);
  EXPECT_LT(StateDistance(dp, Reference()), 1e-10);
  // And the body really tumbled: the rate moved by more than a rad/s.
  EXPECT_GT((Reference().angular_velocity_rad_s - TumblingStart().angular_velocity_rad_s).norm(),
            1.0);
}

TEST(IntegratorConvergenceTest, SemiImplicitEulerIsFirstOrder) {
  for (double order : ObservedOrders(Integrator::kSemiImplicitEuler, 0.01, 3)) {
    EXPECT_NEAR(order, 1.0, 0.3);
  }
}

TEST(IntegratorConvergenceTest, MidpointIsSecondOrder) {
  for (double order : ObservedOrders(Integrator::kMidpoint, 0.01, 3)) {
    EXPECT_NEAR(order, 2.0, 0.3);
  }
}

TEST(IntegratorConvergenceTest, Rk4IsFourthOrder) {
  for (double order : ObservedOrders(Integrator::kRk4, 0.04, 3)) EXPECT_NEAR(order, 4.0, 0.3);
}

// One call over the whole second, so the error control alone sets the substeps.
double DormandPrinceGlobalError(double tolerance, std::uint64_t* accepted) {
  RigidBodyIntegratorOptions options;
  options.tolerance = tolerance;
  return StateDistance(Integrate(Integrator::kDormandPrince, 1.0, 1.0, options, accepted),
                       Reference());
}

TEST(IntegratorConvergenceTest, DormandPrinceMeetsItsTolerance) {
  // Measured: 8.9e-7 in 11 accepted substeps at 1e-6, 6.3e-10 in 41 at 1e-9.
  std::uint64_t loose_steps = 0, tight_steps = 0;
  EXPECT_LT(DormandPrinceGlobalError(1e-6, &loose_steps), 10 * 1e-6);
  EXPECT_LT(DormandPrinceGlobalError(1e-9, &tight_steps), 10 * 1e-9);
  // Step size goes as tol^(1/5): 1000x tighter needs ~4x the substeps.
  EXPECT_GT(loose_steps, 5u);
  EXPECT_GT(tight_steps, 2 * loose_steps);
}

TEST(IntegratorConvergenceTest, DormandPrinceErrorFollowsTolerance) {
  // A loose tolerance must actually be looser, not always tiny: measured 1.2e-4 at 1e-4
  // against 8.9e-7 at 1e-6.
  std::uint64_t steps = 0;
  EXPECT_GT(DormandPrinceGlobalError(1e-4, &steps), 30 * DormandPrinceGlobalError(1e-6, &steps));
}

// ---- Stability on a stiff spring ----------------------------------------------------------

// The object-on-stand stick spring: 9000 N/m on the 0.556 kg vehicle, omega = 127 rad/s.
constexpr double kMass = 0.556;
constexpr double kStiffness = 9000.0;
const double kOmega = std::sqrt(kStiffness / kMass);

struct SpringRun {
  double energy_growth = 0;    // final energy / initial
  double first_half_max = 0;   // largest energy ratio in the first half of the run
  double second_half_max = 0;  // ... and in the second half
  std::uint64_t substeps = 0;
};

double SpringEnergy(const RigidBodyState& state, double stiffness) {
  return 0.5 * kMass * state.velocity_m_s.squaredNorm() +
         0.5 * stiffness * state.position_m.squaredNorm();
}

// A body on the spring along x (no gravity, no rotation), released from 1 cm.
SpringRun RunSpring(Integrator integrator, double omega_dt, int steps, double damping_ratio = 0,
                    const RigidBodyIntegratorOptions& options = {}) {
  RigidBodyParams params;
  params.mass_kg = kMass;
  Wrench wrench;
  wrench.spring_stiffness_n_per_m = kStiffness;
  wrench.spring_damping_n_s_per_m = 2 * damping_ratio * kOmega * kMass;
  RigidBodyState state;
  state.position_m = {0.01, 0.0, 0.0};
  const double initial = SpringEnergy(state, kStiffness);
  const double dt = omega_dt / kOmega;
  SpringRun run;
  for (int i = 0; i < steps && std::isfinite(state.position_m.x()); ++i) {
    IntegratorStats stats;
    state = StepRigidBody(params, state, wrench, 0.0, dt, integrator, options, &stats);
    run.substeps += stats.accepted_substeps + stats.rejected_substeps;
    const double ratio = SpringEnergy(state, kStiffness) / initial;
    double& half_max = i < steps / 2 ? run.first_half_max : run.second_half_max;
    half_max = std::max(half_max, ratio);
  }
  run.energy_growth = SpringEnergy(state, kStiffness) / initial;
  if (!std::isfinite(run.energy_growth)) run.energy_growth = std::numeric_limits<double>::max();
  return run;
}

// Largest omega*dt with |R(z)| <= 1 for z = omega*dt*lambda, lambda the unit-frequency
// eigenvalue of the damped oscillator, found by bisection on the stability function.
template <typename StabilityFunction>
double StabilityLimit(StabilityFunction r, double damping_ratio, double hi) {
  const std::complex<double> lambda(-damping_ratio, std::sqrt(1 - damping_ratio * damping_ratio));
  double lo = 1e-3;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::abs(r(mid * lambda)) <= 1.0 ? lo : hi) = mid;
  }
  return lo;
}

std::complex<double> MidpointR(std::complex<double> z) { return 1.0 + z + z * z / 2.0; }
std::complex<double> Rk4R(std::complex<double> z) {
  return 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
}

TEST(IntegratorStabilityTest, TheoryGivesTheTextbookLimits) {
  // Guards the bisection: RK4 meets the imaginary axis at 2 sqrt(2).
  EXPECT_NEAR(StabilityLimit(Rk4R, 0.0, 3.5), 2.0 * std::sqrt(2.0), 1e-9);
}

// Symplectic Euler on x'' = -w^2 x: the map has trace 2 - (w dt)^2 and determinant 1, so it
// is a rotation (bounded) for w dt < 2 and has a real eigenvalue below -1 above.
TEST(IntegratorStabilityTest, SemiImplicitEulerBoundedJustBelowOmegaDtTwo) {
  const SpringRun run = RunSpring(Integrator::kSemiImplicitEuler, 0.95 * 2.0, 20000);
  // Bounded: no growth from the first to the second half. The energy does swing, by up to
  // (1 + w dt / 2) / (1 - w dt / 2) = 39 at this step.
  EXPECT_LT(run.second_half_max, 1.01 * run.first_half_max);
  EXPECT_LT(run.second_half_max, 40.0);
}

TEST(IntegratorStabilityTest, SemiImplicitEulerGrowsJustAboveOmegaDtTwo) {
  // Eigenvalue -1.37 at w dt = 2.1: energy x1.9 per step.
  EXPECT_GT(RunSpring(Integrator::kSemiImplicitEuler, 1.05 * 2.0, 200).energy_growth, 1e20);
}

TEST(IntegratorStabilityTest, Rk4BoundedJustBelowItsLimit) {
  const double limit = 2.0 * std::sqrt(2.0);
  const SpringRun run = RunSpring(Integrator::kRk4, 0.95 * limit, 20000);
  EXPECT_LE(run.energy_growth, 1.0);  // |R| < 1 inside the region: it even damps
  EXPECT_LE(run.second_half_max, run.first_half_max);
}

TEST(IntegratorStabilityTest, Rk4GrowsJustAboveItsLimit) {
  const double limit = 2.0 * std::sqrt(2.0);
  // |R|^2 = 1.97 per step at 1.05x the limit.
  EXPECT_GT(RunSpring(Integrator::kRk4, 1.05 * limit, 200).energy_growth, 1e20);
}

TEST(IntegratorStabilityTest, MidpointGrowsOnAnUndampedSpringAtAnyStep) {
  // |R(i w dt)|^2 = 1 + (w dt)^4 / 4 > 1: energy grows by exactly that per step (the map is
  // normal in the energy norm), even well inside what looks like a fine step.
  const double omega_dt = 0.5;
  const int steps = 2000;
  const double expected = std::pow(1.0 + std::pow(omega_dt, 4) / 4.0, steps);  // 2.4e6
  EXPECT_NEAR(std::log(RunSpring(Integrator::kMidpoint, omega_dt, steps).energy_growth),
              std::log(expected), 1e-6);
}

// With 10 % damping the oscillator's eigenvalues leave the imaginary axis and midpoint gets a
// real limit (w dt = 1.05 from its stability function).
constexpr double kDamping = 0.1;

TEST(IntegratorStabilityTest, MidpointBoundedJustBelowItsDampedLimit) {
  const double limit = StabilityLimit(MidpointR, kDamping, 2.5);
  const SpringRun run = RunSpring(Integrator::kMidpoint, 0.95 * limit, 20000, kDamping);
  EXPECT_LT(run.energy_growth, 1.0);
  EXPECT_LE(run.second_half_max, run.first_half_max);
}

TEST(IntegratorStabilityTest, MidpointGrowsJustAboveItsDampedLimit) {
  const double limit = StabilityLimit(MidpointR, kDamping, 2.5);
  EXPECT_GT(RunSpring(Integrator::kMidpoint, 1.05 * limit, 20000, kDamping).energy_growth, 1e3);
}

TEST(IntegratorStabilityTest, DormandPrinceStaysBoundedByShrinkingItsSubsteps) {
  // Asked for steps 3x beyond RK4's limit, it substeps under error control instead.
  const SpringRun run = RunSpring(Integrator::kDormandPrince, 3.0 * 2.0 * std::sqrt(2.0), 2000);
  // Measured 0.981 after 2000 steps (133 s, 2700 periods): DP's slight dissipation at 1e-6.
  EXPECT_LT(run.energy_growth, 1.0 + 1e-3);
  EXPECT_GT(run.energy_growth, 0.95);
  EXPECT_GT(run.substeps, 5u * 2000u);
}

// The spring held over the step as an external force (what a caller that samples it once per
// tick does): with the exact constant-force translation of RK4 the map has determinant
// 1 + (w dt)^2 / 2, so it grows at every step size; semi-implicit Euler keeps determinant 1.
double HeldSpringGrowth(Integrator integrator, double omega_dt, int steps) {
  RigidBodyParams params;
  params.mass_kg = kMass;
  RigidBodyState state;
  state.position_m = {0.01, 0.0, 0.0};
  const double initial = SpringEnergy(state, kStiffness);
  for (int i = 0; i < steps; ++i) {
    Wrench wrench;
    wrench.force_world_n = -kStiffness * state.position_m;
    state = StepRigidBody(params, state, wrench, 0.0, omega_dt / kOmega, integrator);
  }
  return SpringEnergy(state, kStiffness) / initial;
}

TEST(IntegratorStabilityTest, SpringHeldOverTheStepGrowsWithRk4) {
  // 1 kHz on the stick spring: w dt = 0.127, energy x(1 + 0.0081) per step, e^8 per second.
  const double omega_dt = kOmega * 1e-3;
  const double expected = std::pow(1.0 + omega_dt * omega_dt / 2.0, 1000);
  const double growth = HeldSpringGrowth(Integrator::kRk4, omega_dt, 1000);
  EXPECT_GT(growth, 0.5 * expected);
  EXPECT_LT(growth, 2.0 * expected);
}

TEST(IntegratorStabilityTest, SpringHeldOverTheStepStaysBoundedWithSemiImplicitEuler) {
  EXPECT_LT(HeldSpringGrowth(Integrator::kSemiImplicitEuler, kOmega * 1e-3, 100000), 1.2);
}

// ---- Bad input ---------------------------------------------------------------------------

TEST(IntegratorInputTest, NonPositiveOrNonFiniteStepReturnsStateUnchangedAndFlagged) {
  const RigidBodyState start = TumblingStart();
  for (double dt : {0.0, -1e-3, std::numeric_limits<double>::quiet_NaN(),
                    std::numeric_limits<double>::infinity()}) {
    for (Integrator integrator : {Integrator::kSemiImplicitEuler, Integrator::kMidpoint,
                                  Integrator::kRk4, Integrator::kDormandPrince}) {
      IntegratorStats stats;
      const RigidBodyState next =
          StepRigidBody(TumblingBody(), start, {}, 9.81, dt, integrator, {}, &stats);
      EXPECT_TRUE(stats.failed);
      EXPECT_EQ(stats.accepted_substeps, 0u);
      EXPECT_EQ(next.angular_velocity_rad_s, start.angular_velocity_rad_s);
    }
  }
}

TEST(IntegratorInputTest, DormandPrinceRejectsAnUnusableTolerance) {
  for (double tolerance : {0.0, -1e-6, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    RigidBodyIntegratorOptions options;
    options.tolerance = tolerance;
    IntegratorStats stats;
    const RigidBodyState next = StepRigidBody(TumblingBody(), TumblingStart(), {}, 9.81, 1e-3,
                                              Integrator::kDormandPrince, options, &stats);
    EXPECT_TRUE(stats.failed);
    EXPECT_TRUE(next.position_m.allFinite());
  }
}

TEST(IntegratorInputTest, DormandPrinceOutOfSubstepsGivesUpWithANonFiniteState) {
  // The stiff spring over a whole second with room for only 10 substeps.
  RigidBodyIntegratorOptions options;
  options.max_substeps = 10;
  Wrench wrench;
  wrench.spring_stiffness_n_per_m = kStiffness;
  RigidBodyState state;
  state.position_m = {0.01, 0.0, 0.0};
  IntegratorStats stats;
  const RigidBodyState next =
      StepRigidBody({}, state, wrench, 0.0, 1.0, Integrator::kDormandPrince, options, &stats);
  EXPECT_TRUE(stats.failed);
  EXPECT_EQ(stats.accepted_substeps + stats.rejected_substeps, 10u);
  EXPECT_FALSE(next.position_m.allFinite());
}

TEST(IntegratorInputTest, FixedStepIntegratorsCountOneSubstep) {
  for (Integrator integrator :
       {Integrator::kSemiImplicitEuler, Integrator::kMidpoint, Integrator::kRk4}) {
    IntegratorStats stats;
    StepRigidBody(TumblingBody(), TumblingStart(), {}, 9.81, 1e-3, integrator, {}, &stats);
    EXPECT_EQ(stats.accepted_substeps, 1u);
    EXPECT_EQ(stats.rejected_substeps, 0u);
    EXPECT_FALSE(stats.failed);
  }
}

TEST(IntegratorInputTest, DormandPrinceAdvancesExactlyDtAcrossSubsteps) {
  // Free fall has a closed form; the substeps must add up to exactly the requested dt.
  Wrench wrench;
  wrench.spring_damping_n_s_per_m = 1e-30;  // forces the staged translation path
  RigidBodyState state;
  state.position_m = {0.0, 0.0, 100.0};
  state.angular_velocity_rad_s = {30.0, -10.0, 20.0};  // the tumbling needs the substeps
  IntegratorStats stats;
  RigidBodyIntegratorOptions options;
  options.tolerance = 1e-12;
  state = StepRigidBody(TumblingBody(), state, wrench, 9.81, 0.7, Integrator::kDormandPrince,
                        options, &stats);
  EXPECT_GT(stats.accepted_substeps, 10u);
  EXPECT_NEAR(state.position_m.z(), 100.0 - 0.5 * 9.81 * 0.49, 1e-9);
  EXPECT_NEAR(state.velocity_m_s.z(), -9.81 * 0.7, 1e-9);
}

}  // namespace
}  // namespace hilrig::host
