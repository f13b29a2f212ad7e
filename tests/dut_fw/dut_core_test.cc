#include "dut_fw/dut_core.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "tests/support/six_pad_tactile.h"

namespace hilrig::dut_fw {
namespace {

constexpr std::int64_t kTickNs = 1'000'000;
constexpr double kDtS = 1e-3;
constexpr std::array<std::uint16_t, 3> kReferenceCodes = {40, 65500, 200};
constexpr std::array<std::uint16_t, 3> kUnloadedCodes = {301, 65000, 8000};
constexpr std::array<std::uint16_t, 3> kLoadedCodes = {301, 65000, 9500};

TactileProcessorParams<double> SixPads() { return SixPadTactile<double>(3); }

DutCoreParams<double> Params(bool tactile) {
  DutCoreParams<double> params;
  params.flight = DefaultFlightControllerParams<double>(0.556);
  if (tactile) params.tactile = SixPads();
  return params;
}

Reference<double> HoverAt1m() {
  Reference<double> reference;
  reference.position_m = Vec3<double>(0, 0, 1);
  reference.velocity_m_s.setZero();
  reference.acceleration_m_s2.setZero();
  reference.yaw_rad = 0;
  return reference;
}

GraspCommand<double> Squeeze() { return {GraspMode::kForce, 0.6, 0.8}; }

void FeedImuAndVio(DutCore<double>& core, std::int64_t now_ns) {
  core.OnImu(Vec3<double>::Zero(), Vec3<double>(0, 0, 9.81), now_ns);
  core.OnVio(Vec3<double>(0, 0, 1), Quat<double>::Identity(), now_ns);
}

void FeedPads(DutCore<double>& core, const std::array<std::uint16_t, 3>& codes,
              std::uint8_t sequence, std::int64_t now_ns) {
  core.OnSensorSample(tactile_bus::kReferenceNodeId, kReferenceCodes, sequence, false, now_ns);
  for (std::uint8_t node = 1; node <= tactile_bus::kTactileNodeCount; ++node) {
    core.OnSensorSample(node, codes, sequence, false, now_ns);
  }
}

TEST(DutCore, StaysDisarmedUntilTheEstimatorHasVio) {
  DutCore<double> core(Params(false));
  core.OnSetpoint(HoverAt1m(), Squeeze());
  core.OnImu(Vec3<double>::Zero(), Vec3<double>(0, 0, 9.81), 0);
  const DutCoreOutput<double> before = core.Step(0, kDtS);
  EXPECT_FALSE(before.armed);
  for (double thrust_n : before.rotor_thrust_n) EXPECT_EQ(thrust_n, 0.0);

  FeedImuAndVio(core, kTickNs);
  const DutCoreOutput<double> after = core.Step(kTickNs, kDtS);
  EXPECT_TRUE(after.armed);
  EXPECT_GT(after.rotor_thrust_n[0], 0.0);
  EXPECT_NEAR(after.estimated_position_m.z(), 1.0, 1e-9);
}

// Without tactile nodes the step is the flight controller's and the grasp controller's own.
TEST(DutCore, StepsTheFlightAndGraspControllersItWires) {
  const DutCoreParams<double> params = Params(false);
  DutCore<double> core(params);
  const FlightController<double> flight(params.flight);
  FlightControllerState<double> flight_state;
  GraspControllerState<double> grasp_state;
  core.OnSetpoint(HoverAt1m(), Squeeze());
  for (int tick = 0; tick < 400; ++tick) {  // past the servo travel hold (0.23 s)
    const std::int64_t now_ns = tick * kTickNs;
    FeedImuAndVio(core, now_ns);
    flight.OnImu(flight_state, Vec3<double>::Zero(), Vec3<double>(0, 0, 9.81), now_ns);
    flight.OnVio(flight_state, Vec3<double>(0, 0, 1), Quat<double>::Identity(), now_ns);
    const DutCoreOutput<double> out = core.Step(now_ns, kDtS);
    const FlightControllerOutput<double> expected =
        flight.Step(flight_state, HoverAt1m(), Vec3<double>::Zero(), kDtS);
    const GraspOutput<double> grasp =
        StepGraspController(params.grasp, grasp_state, Squeeze(), 0.0, false, kDtS);
    EXPECT_EQ(out.rotor_thrust_n, expected.rotor_thrust_n) << "tick " << tick;
    EXPECT_EQ(out.servo_angle_rad, grasp.servo_angle_rad) << "tick " << tick;
    EXPECT_FALSE(out.tactile_ready);
  }
}

constexpr std::int64_t kZeroedNs = 2 * 20 * kTickNs;  // three 50 Hz samples
constexpr std::int64_t kLoadedNs = kZeroedNs + 20 * kTickNs;

// Zeroes every pad on three unloaded samples, then loads them; returns the step after each.
std::array<DutCoreOutput<double>, 2> ZeroThenLoad(DutCore<double>& core) {
  core.OnSetpoint(HoverAt1m(), Squeeze());
  for (std::uint8_t sequence = 0; sequence < 3; ++sequence) {
    FeedPads(core, kUnloadedCodes, sequence, sequence * 20 * kTickNs);
  }
  FeedImuAndVio(core, kZeroedNs);
  const DutCoreOutput<double> unloaded = core.Step(kZeroedNs, kDtS);
  FeedPads(core, kLoadedCodes, 3, kLoadedNs);
  FeedImuAndVio(core, kLoadedNs);
  return {unloaded, core.Step(kLoadedNs, kDtS)};
}

TEST(DutCore, ReadsGraspForceOnceEveryPadIsZeroedAndLoaded) {
  DutCore<double> core(Params(true));
  const auto [unloaded, loaded] = ZeroThenLoad(core);
  EXPECT_TRUE(unloaded.tactile_ready);
  EXPECT_NEAR(unloaded.grasp_force_estimate_n, 0.0, 1e-9);
  EXPECT_TRUE(loaded.tactile_ready);
  EXPECT_GT(loaded.grasp_force_estimate_n, 0.1);
}

TEST(DutCore, FeedsThePadsForceIntoThePositionLoopOnlyWhenAsked) {
  DutCore<double> with_force(Params(true));
  DutCoreParams<double> params_without = Params(true);
  params_without.external_force_in_position_loop = false;
  DutCore<double> without_force(params_without);
  const DutCoreOutput<double> with = ZeroThenLoad(with_force)[1];
  const DutCoreOutput<double> without = ZeroThenLoad(without_force)[1];
  EXPECT_GT(with.external_force_world_n.norm(), 0.1);
  EXPECT_EQ(with.external_force_world_n, without.external_force_world_n);
  EXPECT_NE(with.rotor_thrust_n, without.rotor_thrust_n);
}

TEST(DutCore, DropsStaleTactileForces) {
  DutCore<double> core(Params(true));
  const auto [unloaded, loaded] = ZeroThenLoad(core);
  ASSERT_TRUE(loaded.tactile_ready);
  const std::int64_t stale_ns = kLoadedNs + SixPads().max_sample_age_ns + kTickNs;
  EXPECT_FALSE(core.Step(stale_ns, kDtS).tactile_ready);
}

}  // namespace
}  // namespace hilrig::dut_fw
