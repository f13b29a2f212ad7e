// One simulated hour at 1 kHz: what the integrators conserve (quaternion norm, energy, world
// angular momentum of a torque-free tumble) and that a closed-loop hover under a swaying push
// neither drifts nor gains energy. The bounds are the measured values (stated per test) with some
// headroom.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "dut_fw/flight_controller.h"
#include "host/plant/quadrotor.h"
#include "host/plant/rigid_body.h"

namespace hilrig::host {
namespace {

constexpr int kHourAtOneKilohertz = 3'600'000;
constexpr double kDt = 1e-3;

struct TumbleHour {
  double worst_quaternion_norm_error = 0;
  double worst_energy_drift = 0;    // relative to the start
  double worst_momentum_drift = 0;  // |L - L0| / |L0|
};

// Torque-free, all moments distinct, spinning near the unstable middle axis so the body really
// tumbles (the rate vector wanders over the whole polhode).
TumbleHour RunTumbleHour() {
  RigidBodyParams params;
  params.inertia_kg_m2 = {2e-3, 3e-3, 5e-3};
  RigidBodyState state;
  state.angular_velocity_rad_s = {0.3, 3.0, 0.2};
  const double energy0 = MechanicalEnergy(params, state, 0.0);
  const Eigen::Vector3d momentum0 = AngularMomentumWorld(params, state);
  TumbleHour hour;
  for (int i = 0; i < kHourAtOneKilohertz; ++i) {
    state = StepRigidBody(params, state, {}, 0.0, kDt, Integrator::kRk4);
    hour.worst_quaternion_norm_error =
        std::max(hour.worst_quaternion_norm_error, std::abs(state.orientation.norm() - 1.0));
    if (i % 100 == 0) {
      hour.worst_energy_drift = std::max(
          hour.worst_energy_drift, std::abs(MechanicalEnergy(params, state, 0.0) / energy0 - 1));
      hour.worst_momentum_drift =
          std::max(hour.worst_momentum_drift,
                   (AngularMomentumWorld(params, state) - momentum0).norm() / momentum0.norm());
    }
  }
  return hour;
}

class TumbleHourTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { hour_ = RunTumbleHour(); }
  static TumbleHour hour_;
};
TumbleHour TumbleHourTest::hour_;

TEST_F(TumbleHourTest, QuaternionNormStaysWithinOneEMinus12) {
  EXPECT_LT(hour_.worst_quaternion_norm_error, 1e-12);
}

TEST_F(TumbleHourTest, EnergyDriftStaysBounded) {
  // Measured 2.0e-13 over the hour (RK4's own dissipation, O(h^6) per step, is below the
  // round-off at this rate).
  EXPECT_LT(hour_.worst_energy_drift, 1e-12);
}

TEST_F(TumbleHourTest, WorldAngularMomentumDriftStaysBounded) {
  // Measured 1.1e-12 over the hour.
  EXPECT_LT(hour_.worst_momentum_drift, 5e-12);
}

struct HoverHour {
  double worst_quaternion_norm_error = 0;
  double worst_error_first_ten_min_m = 0;  // after a minute of settling
  double worst_error_last_ten_min_m = 0;
  double worst_energy_first_ten_min_j = 0;  // |E - E_hover| of the swaying vehicle
  double worst_energy_last_ten_min_j = 0;
};

// An hour of closed-loop hover: the firmware's flight controller, fed the true state every tick,
// holds the vehicle against a swaying 0.3 N sideways push (0.5 Hz). Thrust never cancels the
// forces exactly, so the integrator carries real motion all hour; a method that drifts or pumps
// energy in shows as the last ten minutes moving more than the first ten.
HoverHour RunHoverHour(Integrator integrator) {
  QuadrotorParams params;
  params.integrator = integrator;
  const dut_fw::FlightController<double> controller(
      dut_fw::DefaultFlightControllerParams<double>(params.body.mass_kg));
  dut_fw::FlightControllerState<double> firmware;
  const Eigen::Vector3d start(1.0, -2.0, 2.0);
  QuadrotorState state = MakeHoveringQuadrotor(params, start, 0.3);
  dut_fw::Reference<double> reference;
  reference.position_m = start;
  reference.yaw_rad = 0.3;
  const double hover_energy_j = params.body.mass_kg * params.gravity_m_s2 * start.z();
  constexpr int kTicksPerMinute = 60'000;
  HoverHour hour;
  for (int i = 0; i < kHourAtOneKilohertz; ++i) {
    const std::int64_t now_ns = std::int64_t{i} * 1'000'000;
    controller.OnImu(firmware, state.body.angular_velocity_rad_s, state.specific_force_body_m_s2,
                     now_ns);
    controller.OnVio(firmware, state.body.position_m, state.body.orientation, now_ns);
    const auto command = controller.Step(firmware, reference, Eigen::Vector3d::Zero(), kDt);
    const Eigen::Vector3d push_n(0.3 * std::sin(2 * M_PI * 0.5 * i * kDt), 0, 0);
    state = StepQuadrotor(params, state, command.rotor_thrust_n, push_n, kDt);

    hour.worst_quaternion_norm_error =
        std::max(hour.worst_quaternion_norm_error, std::abs(state.body.orientation.norm() - 1.0));
    const double error_m = (state.body.position_m - start).norm();
    const double energy_j =
        std::abs(MechanicalEnergy(params.body, state.body, params.gravity_m_s2) - hover_energy_j);
    if (i >= kTicksPerMinute && i < 11 * kTicksPerMinute) {
      hour.worst_error_first_ten_min_m = std::max(hour.worst_error_first_ten_min_m, error_m);
      hour.worst_energy_first_ten_min_j = std::max(hour.worst_energy_first_ten_min_j, energy_j);
    } else if (i >= 50 * kTicksPerMinute) {
      hour.worst_error_last_ten_min_m = std::max(hour.worst_error_last_ten_min_m, error_m);
      hour.worst_energy_last_ten_min_j = std::max(hour.worst_energy_last_ten_min_j, energy_j);
    }
  }
  EXPECT_FALSE(state.on_ground);
  return hour;
}

void ExpectSteadyHour(const HoverHour& hour) {
  EXPECT_LT(hour.worst_quaternion_norm_error, 1e-12);
  // The push sways it by about 5 cm (measured 5.2 cm with either integrator); the hour's end must
  // look like its start.
  EXPECT_LT(hour.worst_error_first_ten_min_m, 0.1);
  EXPECT_GT(hour.worst_error_first_ten_min_m, 1e-4);  // it really moves
  EXPECT_LT(hour.worst_error_last_ten_min_m, 1.05 * hour.worst_error_first_ten_min_m);
  EXPECT_LT(hour.worst_energy_last_ten_min_j, 1.05 * hour.worst_energy_first_ten_min_j + 1e-9);
}

TEST(HoverHourTest, SemiImplicitEulerHoldsAClosedLoopHoverForAnHour) {
  ExpectSteadyHour(RunHoverHour(Integrator::kSemiImplicitEuler));
}

TEST(HoverHourTest, Rk4HoldsAClosedLoopHoverForAnHour) {
  ExpectSteadyHour(RunHoverHour(Integrator::kRk4));
}

}  // namespace
}  // namespace hilrig::host
