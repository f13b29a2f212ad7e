#include "dut_fw/position_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class PositionControllerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(PositionControllerTest, Scalars);

constexpr double kMassKg = 0.556;
constexpr double kG = 9.81;
constexpr double kMaxTiltRad = 35.0 * M_PI / 180.0;

template <typename S>
PositionGains<S> Gains() {
  PositionGains<S> g;
  g.kp_per_s2 = Vec3<S>(S(6.25), S(6.25), S(9));
  g.kv_per_s = Vec3<S>(S(4.5), S(4.5), S(6));
  g.mass_kg = S(kMassKg);
  g.gravity_m_s2 = S(kG);
  g.max_tilt_rad = S(kMaxTiltRad);
  g.min_collective_thrust_n = S(0.5);
  g.max_collective_thrust_n = S(14.4);
  return g;
}

template <typename S>
Reference<S> At(S x, S y, S z, S yaw_rad = S(0)) {
  Reference<S> r;
  r.position_m = Vec3<S>(x, y, z);
  r.yaw_rad = yaw_rad;
  return r;
}

template <typename S>
double TiltRad(const Quat<S>& q) {
  return std::acos(std::clamp(double((q * Vec3<S>::UnitZ()).z()), -1.0, 1.0));
}

TYPED_TEST(PositionControllerTest, HoverGivesWeightAndLevelAttitude) {
  using S = TypeParam;
  const Vec3<S> here(S(1), S(2), S(1));

  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(1), S(2), S(1)), here, Vec3<S>::Zero(), Quat<S>::Identity());

  EXPECT_NEAR(cmd.collective_thrust_n, kMassKg * kG, 1e-5);
  EXPECT_NEAR(cmd.thrust_world_n.x(), 0.0, 1e-6);
  EXPECT_NEAR(cmd.thrust_world_n.y(), 0.0, 1e-6);
  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * kG, 1e-5);
  EXPECT_NEAR(cmd.attitude_desired.angularDistance(Quat<S>::Identity()), 0.0, 1e-3);
}

TYPED_TEST(PositionControllerTest, PositionErrorTiltsTowardTheTarget) {
  using S = TypeParam;

  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(0.1), S(0), S(0)), Vec3<S>::Zero(), Vec3<S>::Zero(), Quat<S>::Identity());

  // F_x = m kp dx, F_z = m g.
  EXPECT_NEAR(cmd.thrust_world_n.x(), kMassKg * 6.25 * 0.1, 1e-5);
  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * kG, 1e-5);
  const Vec3<S> body_z = cmd.attitude_desired * Vec3<S>::UnitZ();
  EXPECT_NEAR(body_z.x(), std::sin(std::atan(6.25 * 0.1 / kG)), 1e-5);
  EXPECT_NEAR(body_z.y(), 0.0, 1e-6);
}

TYPED_TEST(PositionControllerTest, TiltLimitIsRespectedAndAltitudeKept) {
  using S = TypeParam;

  const PositionCommand<S> cmd =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(10), S(-10), S(0)), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity());

  EXPECT_NEAR(TiltRad(cmd.attitude_desired), kMaxTiltRad, 1e-4);
  const Vec3<S>& f = cmd.thrust_world_n;
  EXPECT_NEAR(std::atan2(std::hypot(double(f.x()), double(f.y())), double(f.z())), kMaxTiltRad,
              1e-5);
  EXPECT_NEAR(f.z(), kMassKg * kG, 1e-5);  // vertical part untouched
  EXPECT_NEAR(f.x(), -f.y(), 1e-5);        // direction of the error kept
  EXPECT_GT(f.x(), 0.0);
}

TYPED_TEST(PositionControllerTest, ThrustLimitShortensHorizontalFirst) {
  using S = TypeParam;

  // 10 m below and 10 m beside the target: F_z alone asks for ~55 N.
  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(10), S(0), S(10)), Vec3<S>::Zero(), Vec3<S>::Zero(), Quat<S>::Identity());

  EXPECT_NEAR(cmd.thrust_world_n.z(), 14.4, 1e-5);
  EXPECT_NEAR(cmd.thrust_world_n.x(), 0.0, 1e-5);
  EXPECT_NEAR(cmd.collective_thrust_n, 14.4, 1e-5);
}

TYPED_TEST(PositionControllerTest, ThrustNeverPullsDown) {
  using S = TypeParam;

  // 10 m above the target with a sideways error: asks for strongly negative F_z.
  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(3), S(0), S(-10)), Vec3<S>::Zero(), Vec3<S>::Zero(), Quat<S>::Identity());

  EXPECT_NEAR(cmd.thrust_world_n.z(), 0.5, 1e-6);  // floored at the minimum collective
  EXPECT_NEAR(cmd.collective_thrust_n, 0.5, 1e-6);
  EXPECT_LE(TiltRad(cmd.attitude_desired), kMaxTiltRad + 1e-4);
}

TYPED_TEST(PositionControllerTest, YawIsFollowed) {
  using S = TypeParam;
  const S yaw_rad = S(1.2);

  const PositionCommand<S> level =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0), yaw_rad), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity());
  const PositionCommand<S> tilted =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0.2), S(0.1), S(0), yaw_rad), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity());

  const Vec3<S> level_x = level.attitude_desired * Vec3<S>::UnitX();
  EXPECT_NEAR(level_x.x(), std::cos(1.2), 1e-5);
  EXPECT_NEAR(level_x.y(), std::sin(1.2), 1e-5);
  EXPECT_NEAR(level_x.z(), 0.0, 1e-6);
  const Vec3<S> tilted_x = tilted.attitude_desired * Vec3<S>::UnitX();
  EXPECT_NEAR(std::atan2(tilted_x.y(), tilted_x.x()), 1.2, 1e-5);
}

TYPED_TEST(PositionControllerTest, CollectiveIsProjectionOnCurrentBodyZ) {
  using S = TypeParam;
  const Quat<S> rolled(Eigen::AngleAxis<S>(S(0.35), Vec3<S>::UnitX()));

  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(0), S(0), S(1)), Vec3<S>(S(0), S(0), S(1)), Vec3<S>::Zero(), rolled);

  EXPECT_NEAR(cmd.collective_thrust_n, kMassKg * kG * std::cos(0.35), 1e-5);
  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * kG, 1e-5);
}

TYPED_TEST(PositionControllerTest, VelocityAndFeedForwardTermsAdd) {
  using S = TypeParam;
  Reference<S> desired = At<S>(S(0), S(0), S(0));
  desired.velocity_m_s = Vec3<S>(S(0), S(0), S(0.5));
  desired.acceleration_m_s2 = Vec3<S>(S(0), S(0), S(1));

  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), desired, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(0.2)), Quat<S>::Identity());

  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * (1.0 + 6.0 * 0.3 + kG), 1e-5);
}

TYPED_TEST(PositionControllerTest, NonFiniteInputFallsBackToLevelHover) {
  using S = TypeParam;
  const Vec3<S> bad(std::numeric_limits<S>::quiet_NaN(), S(0), S(0));

  const PositionCommand<S> cmd = ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0)), bad,
                                                           Vec3<S>::Zero(), Quat<S>::Identity());

  EXPECT_NEAR(cmd.collective_thrust_n, kMassKg * kG, 1e-5);
  EXPECT_NEAR(cmd.attitude_desired.angularDistance(Quat<S>::Identity()), 0.0, 1e-3);
}

TYPED_TEST(PositionControllerTest, HeldLoadIsCarriedByTheThrust) {
  using S = TypeParam;
  const Vec3<S> here(S(0), S(0), S(1));
  const Vec3<S> load_n(S(0), S(0), S(-1.77));  // a held 180 g bottle pulls the vehicle down

  const PositionCommand<S> cmd = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(0), S(0), S(1)), here, Vec3<S>::Zero(), Quat<S>::Identity(), load_n);

  EXPECT_NEAR(cmd.collective_thrust_n, kMassKg * kG + 1.77, 1e-5);
  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * kG + 1.77, 1e-5);
  EXPECT_NEAR(cmd.attitude_desired.angularDistance(Quat<S>::Identity()), 0.0, 1e-3);
}

TYPED_TEST(PositionControllerTest, SidewaysContactForceIsOpposed) {
  using S = TypeParam;
  const Vec3<S> push_n(S(0.3), S(-0.2), S(0));

  const PositionCommand<S> cmd =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0)), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity(), push_n);

  EXPECT_NEAR(cmd.thrust_world_n.x(), -0.3, 1e-6);
  EXPECT_NEAR(cmd.thrust_world_n.y(), 0.2, 1e-6);
  EXPECT_NEAR(cmd.thrust_world_n.z(), kMassKg * kG, 1e-5);
}

TYPED_TEST(PositionControllerTest, LoadFeedForwardIsLimitedLikeTheRest) {
  using S = TypeParam;
  const Vec3<S> lift_n(S(0), S(0), S(10));    // contacts pushing up harder than the weight
  const Vec3<S> heavy_n(S(0), S(0), S(-20));  // a load beyond the rotors

  const PositionCommand<S> lifted =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0)), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity(), lift_n);
  const PositionCommand<S> heavy =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0)), Vec3<S>::Zero(),
                                Vec3<S>::Zero(), Quat<S>::Identity(), heavy_n);

  EXPECT_NEAR(lifted.collective_thrust_n, 0.5, 1e-6);  // m g − 10 < 0: the floor
  EXPECT_NEAR(heavy.collective_thrust_n, 14.4, 1e-5);  // m g + 20 > max: the cap
}

TYPED_TEST(PositionControllerTest, NonFiniteExternalForceIsIgnored) {
  using S = TypeParam;
  const Vec3<S> here(S(0.1), S(0), S(1));
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const S inf = std::numeric_limits<S>::infinity();

  const PositionCommand<S> zero = ComputePositionCommand<S>(
      Gains<S>(), At<S>(S(0), S(0), S(1)), here, Vec3<S>::Zero(), Quat<S>::Identity());
  for (const Vec3<S>& bad_n : {Vec3<S>(nan, S(0), S(-1.77)), Vec3<S>(S(0), S(0), -inf)}) {
    const PositionCommand<S> cmd = ComputePositionCommand<S>(
        Gains<S>(), At<S>(S(0), S(0), S(1)), here, Vec3<S>::Zero(), Quat<S>::Identity(), bad_n);

    EXPECT_EQ(cmd.thrust_world_n, zero.thrust_world_n);
    EXPECT_EQ(cmd.collective_thrust_n, zero.collective_thrust_n);
  }
}

TYPED_TEST(PositionControllerTest, NonFiniteStateFallsBackToHoverCarryingTheLoad) {
  using S = TypeParam;
  const Vec3<S> bad(std::numeric_limits<S>::quiet_NaN(), S(0), S(0));

  const PositionCommand<S> cmd =
      ComputePositionCommand<S>(Gains<S>(), At<S>(S(0), S(0), S(0)), bad, Vec3<S>::Zero(),
                                Quat<S>::Identity(), Vec3<S>(S(0), S(0), S(-1.77)));

  EXPECT_NEAR(cmd.collective_thrust_n, kMassKg * kG + 1.77, 1e-5);
  EXPECT_NEAR(cmd.attitude_desired.angularDistance(Quat<S>::Identity()), 0.0, 1e-3);
}

TYPED_TEST(PositionControllerTest, YawTrigIsReusedWhileTheYawStaysTheSame) {
  using S = TypeParam;
  // Deliberately not cos/sin of 0.15: only a reuse can return these.
  HalfYawTrig<S> cache{S(0.3), S(5), S(7)};

  const HalfYawTrig<S>& trig = YawTrigFor<S>(cache, S(0.3));

  EXPECT_EQ(trig.cos_half, S(5));
  EXPECT_EQ(trig.sin_half, S(7));
}

TYPED_TEST(PositionControllerTest, YawTrigIsRecomputedWhenTheYawChanges) {
  using S = TypeParam;
  HalfYawTrig<S> cache{S(0.3), S(5), S(7)};

  const HalfYawTrig<S>& trig = YawTrigFor<S>(cache, S(-1.4));

  EXPECT_EQ(trig.yaw_rad, S(-1.4));
  EXPECT_NEAR(trig.cos_half, std::cos(-0.7), 1e-6);
  EXPECT_NEAR(trig.sin_half, std::sin(-0.7), 1e-6);
}

TYPED_TEST(PositionControllerTest, YawTrigTellsNegativeZeroFromZero) {
  using S = TypeParam;
  HalfYawTrig<S> cache;  // yaw +0: (1, +0)

  const HalfYawTrig<S>& trig = YawTrigFor<S>(cache, -S(0));

  EXPECT_TRUE(std::signbit(trig.yaw_rad));
  EXPECT_TRUE(std::signbit(trig.sin_half));
}

TYPED_TEST(PositionControllerTest, ControllerYawTrigFollowsAYawStep) {
  using S = TypeParam;
  HalfYawTrig<S> yaw_trig;
  const auto step = [&](S yaw_rad) {
    return ComputePositionCommandWithTiltTangent<S>(
        Gains<S>(), MaxTiltTangent(Gains<S>()), yaw_trig, At<S>(S(0), S(0), S(0), yaw_rad),
        Vec3<S>::Zero(), Vec3<S>::Zero(), Quat<S>::Identity(), Vec3<S>::Zero());
  };
  step(S(0.5));

  const PositionCommand<S> cmd = step(S(2.0));

  // Level thrust: the desired attitude is the pure yaw rotation (cos 1, 0, 0, sin 1).
  EXPECT_NEAR(cmd.attitude_desired.w(), std::cos(1.0), 1e-6);
  EXPECT_NEAR(cmd.attitude_desired.z(), std::sin(1.0), 1e-6);
  EXPECT_NEAR(cmd.attitude_desired.x(), 0.0, 1e-6);
  EXPECT_NEAR(cmd.attitude_desired.y(), 0.0, 1e-6);
}

}  // namespace
}  // namespace hilrig::dut_fw
