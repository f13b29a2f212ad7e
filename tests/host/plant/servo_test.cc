#include "host/plant/servo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

constexpr double kDt = 1e-3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Zero up to `contact_rad`, then a linear spring; only TorqueAt, so the search uses the base
// class's numerical slope.
class SpringLoad final : public ServoLoad {
 public:
  SpringLoad(double contact_rad, double stiffness_nm_per_rad)
      : contact_rad_(contact_rad), stiffness_(stiffness_nm_per_rad) {}
  double TorqueAt(double angle_rad) const override {
    return angle_rad > contact_rad_ ? stiffness_ * (angle_rad - contact_rad_) : 0.0;
  }

 private:
  double contact_rad_;
  double stiffness_;
};

TEST(ServoTest, NoLoadSlewsAtMaxRate) {
  const ServoParams params;  // 6 rad/s, tau 30 ms
  ServoState state;
  for (int i = 0; i < 100; ++i) state = StepServo(params, state, 1.0, NoServoLoad(), kDt);
  // Far from the command the first-order step (1 - e^(-1/30)) x 0.4 rad exceeds 6 mrad/step.
  EXPECT_NEAR(state.angle_rad, 0.6, 1e-12);
  EXPECT_NEAR(state.rate_rad_s, 6.0, 1e-9);
  EXPECT_FALSE(state.stalled);
}

TEST(ServoTest, NoLoadEndsWithTheLoopTimeConstant) {
  const ServoParams params;
  ServoState state;
  // Slew until the rate limit lets go: the remaining error then decays as exp(-t / 30 ms).
  while (state.rate_rad_s == 0.0 || std::abs(state.rate_rad_s - 6.0) < 1e-9) {
    state = StepServo(params, state, 1.0, NoServoLoad(), kDt);
  }
  const double remaining = 1.0 - state.angle_rad;
  ASSERT_GT(remaining, 0.1);
  ASSERT_LT(remaining, 0.19);  // 6e-3 / (1 - e^(-1/30)) = 0.183 rad is where the limit ends
  for (int i = 0; i < 30; ++i) state = StepServo(params, state, 1.0, NoServoLoad(), kDt);
  EXPECT_NEAR(1.0 - state.angle_rad, remaining * std::exp(-1.0), 1e-12);
  for (int i = 0; i < 1000; ++i) state = StepServo(params, state, 1.0, NoServoLoad(), kDt);
  EXPECT_NEAR(state.angle_rad, 1.0, 1e-12);
}

TEST(ServoTest, CommandIsClampedToTheTravel) {
  const ServoParams params;
  EXPECT_EQ(ServoEquilibriumAngle(params, 3.0, NoServoLoad(), 0.0), 1.6);
  EXPECT_EQ(ServoEquilibriumAngle(params, -1.0, NoServoLoad(), 0.5), 0.0);
}

TEST(ServoTest, StallTorqueStopsItAgainstAStiffWall) {
  // A wall at 0.5 rad with 1000 N m/rad: the servo, commanded to 1.5 rad, is saturated
  // (K x 1 rad = 5 N m > 0.25) and stops where the wall pushes back with the stall torque.
  const ServoParams params;
  const SpringLoad wall(0.5, 1000.0);
  ServoState state;
  for (int i = 0; i < 2000; ++i) state = StepServo(params, state, 1.5, wall, kDt);
  EXPECT_NEAR(state.angle_rad, 0.5 + 0.25 / 1000.0, 1e-9);
  EXPECT_TRUE(state.stalled);
  EXPECT_NEAR(state.rate_rad_s, 0.0, 1e-6);
}

TEST(ServoTest, EquilibriumAgainstASpringMatchesClosedForm) {
  // Unsaturated: K (c - a) = k (a - a0)  ->  a = (K c + k a0) / (K + k).
  const ServoParams params;  // K = 5
  const SpringLoad spring(0.5, 5.0);
  EXPECT_NEAR(ServoEquilibriumAngle(params, 0.52, spring, 0.0), (5.0 * 0.52 + 5.0 * 0.5) / 10.0,
              1e-10);
}

TEST(ServoTest, EquilibriumAgainstASoftSpringSaturates) {
  // Linear-band guess (5 x 1.5 + 0.5) / 6 = 1.33 would need 0.83 N m; the servo only has 0.25,
  // so it stops where the spring reaches the stall torque: 0.5 + 0.25 / 1.
  const ServoParams params;
  const SpringLoad spring(0.5, 1.0);
  EXPECT_NEAR(ServoEquilibriumAngle(params, 1.5, spring, 1.0), 0.75, 1e-10);
}

TEST(ServoTest, SpringStepConvergesToTheEquilibriumAndFlagsStall) {
  const ServoParams params;
  const SpringLoad spring(0.5, 5.0);
  ServoState state;
  for (int i = 0; i < 3000; ++i) state = StepServo(params, state, 0.52, spring, kDt);
  EXPECT_NEAR(state.angle_rad, 0.51, 1e-9);
  EXPECT_TRUE(state.stalled);  // 10 mrad short of the command
}

TEST(ServoTest, EquilibriumDoesNotDependOnTheHint) {
  const ServoParams params;
  const SpringLoad spring(0.5, 20.0);  // (5 x 0.55 + 20 x 0.5) / 25 = 0.51, at 0.2 N m < stall
  for (double hint : {0.0, 0.3, 0.52, 0.6, 1.6, -5.0, kNaN}) {
    EXPECT_NEAR(ServoEquilibriumAngle(params, 0.55, spring, hint), 0.51, 1e-10) << hint;
  }
}

TEST(ServoTest, LoadAtTheOpenStopKeepsItThere) {
  const ServoParams params;
  const SpringLoad preload(-1.0, 1.0);  // 1 N m already at angle 0
  EXPECT_EQ(ServoEquilibriumAngle(params, 1.0, preload, 0.3), 0.0);
}

TEST(ServoTest, NaNCommandHoldsTheAngle) {
  const ServoParams params;
  ServoState state;
  state.angle_rad = 0.7;
  state.rate_rad_s = 3.0;
  for (int i = 0; i < 100; ++i) state = StepServo(params, state, kNaN, NoServoLoad(), kDt);
  EXPECT_EQ(state.angle_rad, 0.7);
  EXPECT_EQ(state.rate_rad_s, 0.0);
  state = StepServo(params, state, std::numeric_limits<double>::infinity(), NoServoLoad(), kDt);
  EXPECT_EQ(state.angle_rad, 0.7);
}

TEST(ServoTest, BadStepOrParamsLeaveTheAngle) {
  ServoParams params;
  ServoState state;
  state.angle_rad = 0.4;
  EXPECT_EQ(StepServo(params, state, 1.0, NoServoLoad(), kNaN).angle_rad, 0.4);
  EXPECT_EQ(StepServo(params, state, 1.0, NoServoLoad(), -1e-3).angle_rad, 0.4);
  params.stall_torque_nm = kNaN;
  EXPECT_EQ(StepServo(params, state, 1.0, NoServoLoad(), kDt).angle_rad, 0.4);
}

TEST(ServoTest, NonFiniteStateAngleRestartsOpen) {
  const ServoParams params;
  ServoState state;
  state.angle_rad = kNaN;
  const ServoState next = StepServo(params, state, 0.0, NoServoLoad(), kDt);
  EXPECT_EQ(next.angle_rad, 0.0);
  EXPECT_TRUE(std::isfinite(next.rate_rad_s));
}

TEST(ServoTest, LagDecayIsTheExponentialOfMinusDtOverTau) {
  ServoParams params;                                                   // tau 30 ms
  EXPECT_NEAR(ServoLagDecay(params, kDt), 0.96721610048200596, 1e-15);  // e^(-1/30)
  params.time_constant_s = 0.0;
  EXPECT_EQ(ServoLagDecay(params, kDt), 0.0);  // no lag: the servo jumps to the equilibrium
}

TEST(ServoTest, StepWithPrecomputedDecayMatchesStepServoExactly) {
  const ServoParams params;
  const SpringLoad spring(0.5, 2.0);
  ServoState plain;
  ServoState precomputed;
  const double decay = ServoLagDecay(params, kDt);
  for (int i = 0; i < 300; ++i) {
    plain = StepServo(params, plain, 0.9, spring, kDt);
    precomputed = StepServoWithDecay(params, precomputed, 0.9, spring, kDt, decay);
  }
  EXPECT_GT(plain.angle_rad, 0.5);  // it reached the spring and works against it
  EXPECT_EQ(precomputed.angle_rad, plain.angle_rad);
  EXPECT_EQ(precomputed.rate_rad_s, plain.rate_rad_s);
  EXPECT_EQ(precomputed.stalled, plain.stalled);
}

TEST(ServoTest, ValidateNamesTheField) {
  EXPECT_TRUE(ValidateServo(ServoParams{}).ok());
  ServoParams params;
  params.max_angle_rad = -1.0;
  const auto result = ValidateServo(params);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("max_angle_rad"), std::string::npos);
}

}  // namespace
}  // namespace hilrig::host
