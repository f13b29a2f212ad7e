#include "dut_fw/grasp_controller.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class GraspControllerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(GraspControllerTest, Scalars);

constexpr double kDtS = 1e-3;             // control step
constexpr int kTicksPerForceSample = 20;  // tactile force at 50 Hz
constexpr double kServoLagS = 0.03;
constexpr double kBalloonNPerRad = 75.0;
constexpr double kRigidNPerRad = 840.0;
constexpr double kContactRad = 0.8;

template <typename S>
S NaN() {
  return std::numeric_limits<S>::quiet_NaN();
}

template <typename S>
S Inf() {
  return std::numeric_limits<S>::infinity();
}

// Rounding allowance for comparing a few float or double operations with their exact value.
template <typename S>
double Tol() {
  return std::is_same_v<S, float> ? 2e-6 : 1e-12;
}

template <typename S>
GraspCommand<S> Squeeze(double force_n, double reference_angle_rad = kContactRad) {
  return {GraspMode::kForce, S(force_n), S(reference_angle_rad)};
}

template <typename S>
GraspCommand<S> Open() {
  return {GraspMode::kOpen, S(0), S(0)};
}

// A linear grasp, F = k_g max(0, θ − θ_contact), behind a first-order servo lag, whose force the
// controller only sees as a 50 Hz zero-order hold: the loop of docs/design.md section 1 without the
// host's models.
struct GraspPlant {
  double stiffness_n_per_rad;
  double contact_angle_rad = kContactRad;
  double servo_angle_rad = 0.0;  // starts fully open
  double sampled_force_n = 0.0;
  std::int64_t tick = 0;

  double ForceN() const {
    return stiffness_n_per_rad * std::max(0.0, servo_angle_rad - contact_angle_rad);
  }
  void Sample() {
    if (tick % kTicksPerForceSample == 0) sampled_force_n = ForceN();
  }
  void Advance(double command_rad) {
    servo_angle_rad += (1.0 - std::exp(-kDtS / kServoLagS)) * (command_rad - servo_angle_rad);
    ++tick;
  }
};

struct RunResult {
  double peak_force_n = 0.0;
  double min_force_n = std::numeric_limits<double>::infinity();  // over the tail window
  double max_force_n = 0.0;                                      // over the tail window
};

// Runs the closed loop for `duration_s`, recording the true force's peak over the whole run and
// its range over the last `tail_s`.
template <typename S>
RunResult RunClosedLoop(const GraspAdmittanceParams<S>& params, GraspControllerState<S>& state,
                        GraspPlant& plant, const GraspCommand<S>& command, double duration_s,
                        double tail_s) {
  RunResult result;
  const int steps = int(std::lround(duration_s / kDtS));
  const int tail_from = steps - int(std::lround(tail_s / kDtS));
  for (int i = 0; i < steps; ++i) {
    plant.Sample();
    const GraspOutput<S> out =
        StepGraspController<S>(params, state, command, S(plant.sampled_force_n), true, S(kDtS));
    plant.Advance(double(out.servo_angle_rad));
    const double force_n = plant.ForceN();
    result.peak_force_n = std::max(result.peak_force_n, force_n);
    if (i >= tail_from) {
      result.min_force_n = std::min(result.min_force_n, force_n);
      result.max_force_n = std::max(result.max_force_n, force_n);
    }
  }
  return result;
}

// Regulates a grasp from fully open for 6 s and checks the last second.
template <typename S>
void ExpectRegulates(double stiffness_n_per_rad) {
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  GraspPlant plant{stiffness_n_per_rad};

  const RunResult run = RunClosedLoop<S>(params, state, plant, Squeeze<S>(0.6), 6.0, 1.0);

  EXPECT_GT(run.min_force_n, 0.6 * 0.99);
  EXPECT_LT(run.max_force_n, 0.6 * 1.01);
  EXPECT_LT(run.peak_force_n, 0.6 * 1.15);  // a balloon bursts on overshoot
  EXPECT_EQ(state.rejected_inputs, 0u);
}

TYPED_TEST(GraspControllerTest, RegulatesABalloonWithinOnePercentWithoutOvershoot) {
  ExpectRegulates<TypeParam>(kBalloonNPerRad);
}

TYPED_TEST(GraspControllerTest, RegulatesARigidObjectWithinOnePercentWithoutOvershoot) {
  ExpectRegulates<TypeParam>(kRigidNPerRad);
}

TYPED_TEST(GraspControllerTest, FollowsForceSteps) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  GraspPlant plant{kBalloonNPerRad};

  for (const double force_n : {0.6, 0.3, 0.6}) {
    const RunResult run = RunClosedLoop<S>(params, state, plant, Squeeze<S>(force_n), 6.0, 0.5);

    EXPECT_GT(run.min_force_n, force_n * 0.99) << force_n;
    EXPECT_LT(run.max_force_n, force_n * 1.01) << force_n;
  }
}

TYPED_TEST(GraspControllerTest, WithoutForceFeedbackCommandsTheClosedAngle) {
  using S = TypeParam;
  GraspAdmittanceParams<S> params;
  params.force_feedback = false;
  GraspControllerState<S> state;

  for (const S force_n : {S(0), S(0.6), S(50), NaN<S>()}) {
    const GraspOutput<S> out =
        StepGraspController<S>(params, state, Squeeze<S>(0.6), force_n, true, S(kDtS));

    EXPECT_EQ(out.servo_angle_rad, S(1.6));
    EXPECT_FALSE(out.regulating);
    EXPECT_EQ(out.force_error_n, S(0));
  }
}

TYPED_TEST(GraspControllerTest, OpenCommandsTheOpenAngleAndResetsTheOffset) {
  using S = TypeParam;
  GraspAdmittanceParams<S> params;
  params.open_angle_rad = S(0.1);
  GraspControllerState<S> state;
  GraspPlant plant{kBalloonNPerRad};
  RunClosedLoop<S>(params, state, plant, Squeeze<S>(0.6), 2.0, 0.0);
  ASSERT_GT(state.offset_rad, S(0.005));  // squeezing: the offset is what gives the force

  const GraspOutput<S> open =
      StepGraspController<S>(params, state, Open<S>(), S(0.6), true, S(kDtS));

  EXPECT_EQ(open.servo_angle_rad, S(0.1));
  EXPECT_FALSE(open.regulating);
  EXPECT_EQ(state.offset_rad, S(0));
  EXPECT_EQ(state.offset_rate_rad_s, S(0));
}

TYPED_TEST(GraspControllerTest, NewGraspStartsAtTheReferenceAngle) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  state.offset_rad = S(0.3);  // left over from an earlier grasp
  state.offset_rate_rad_s = S(0.1);
  state.last_mode = GraspMode::kOpen;

  const GraspOutput<S> out =
      StepGraspController<S>(params, state, Squeeze<S>(0.6, 0.5), S(0.2), true, S(kDtS));

  EXPECT_EQ(out.servo_angle_rad, S(0.5));
  EXPECT_EQ(state.offset_rad, S(0));
  EXPECT_EQ(state.offset_rate_rad_s, S(0));
}

TYPED_TEST(GraspControllerTest, WithoutTravelHoldTheFirstStepIntegrates) {
  using S = TypeParam;
  GraspAdmittanceParams<S> params;
  params.servo_max_rate_rad_s = Inf<S>();
  params.servo_settle_s = S(0);
  GraspControllerState<S> state;

  const GraspOutput<S> out =
      StepGraspController<S>(params, state, Squeeze<S>(0.6, 0.5), S(0.2), true, S(kDtS));

  // From Δθ = 0 at rest, one semi-implicit step: Δθ = (e / M) dt², e = 0.6 − 0.2.
  EXPECT_TRUE(out.regulating);
  EXPECT_NEAR(out.force_error_n, 0.4, 1e-6);
  EXPECT_NEAR(out.servo_angle_rad, 0.5 + 0.4 / 0.2 * kDtS * kDtS, Tol<S>());
}

// Steps a new grasp from fully open with a constant force estimate; the step index (from 0) of the
// first one that regulates, or -1.
template <typename S>
int FirstRegulatingStep(const GraspAdmittanceParams<S>& params, S force_estimate_n, int steps) {
  GraspControllerState<S> state;
  StepGraspController<S>(params, state, Open<S>(), S(0), true, S(kDtS));
  for (int i = 0; i < steps; ++i) {
    const GraspOutput<S> out = StepGraspController<S>(params, state, Squeeze<S>(0.6, 0.6),
                                                      force_estimate_n, true, S(kDtS));
    if (out.regulating) return i;
    EXPECT_EQ(out.servo_angle_rad, S(0.6)) << i;  // held at θ_r while the servo travels
  }
  return -1;
}

TYPED_TEST(GraspControllerTest, TravelHoldLastsForTheServoTravel) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;

  const int first = FirstRegulatingStep<S>(params, S(0), 400);

  // 0.6 rad at 6 rad/s plus 0.1 s of settling: 0.2 s, i.e. 200 steps of 1 ms (± rounding).
  EXPECT_GE(first, 199);
  EXPECT_LE(first, 201);
}

TYPED_TEST(GraspControllerTest, TravelHoldEndsWhenTheForceIsAlreadyThere) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;

  // θ_r past the contact: the pads already feel more than f_d, so the loop must back off at once.
  EXPECT_EQ(FirstRegulatingStep<S>(params, S(0.9), 400), 0);
}

TYPED_TEST(GraspControllerTest, TravelHoldRunsDownWhileTheEstimateIsInvalid) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;

  // The servo travels for 0.2 s whether or not the pads are ready (see the test above).
  for (int i = 0; i < 300; ++i) {
    StepGraspController<S>(params, state, Squeeze<S>(0.6, 0.6), S(0), false, S(kDtS));
  }
  const GraspOutput<S> out =
      StepGraspController<S>(params, state, Squeeze<S>(0.6, 0.6), S(0), true, S(kDtS));

  EXPECT_TRUE(out.regulating);
  EXPECT_EQ(state.rejected_inputs, 300u);
}

TYPED_TEST(GraspControllerTest, AbsentObjectRestsOnTheClosedLimitWithoutWindup) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  // f̂ = 0 closes at f_d / B ≈ 9.2 mrad/s: 0.8 rad to the limit takes ≈ 87 s.
  GraspOutput<S> out;
  for (int i = 0; i < 120'000; ++i) {
    out = StepGraspController<S>(params, state, Squeeze<S>(0.6), S(0), true, S(kDtS));
  }
  ASSERT_EQ(out.servo_angle_rad, S(1.6));
  EXPECT_EQ(state.offset_rad, S(1.6) - S(kContactRad));
  EXPECT_EQ(state.offset_rate_rad_s, S(0));

  const GraspOutput<S> back =
      StepGraspController<S>(params, state, Squeeze<S>(0.6), S(1.0), true, S(kDtS));

  // From rest at the limit: Δθ falls by (f̂ − f_d) / M dt² in the first step.
  EXPECT_LT(back.servo_angle_rad, S(1.6));
  EXPECT_NEAR(back.servo_angle_rad, 1.6 - 0.4 / 0.2 * kDtS * kDtS, Tol<S>());
}

TYPED_TEST(GraspControllerTest, InvalidOrNonFiniteEstimateHoldsTheCommandAndCounts) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  GraspPlant plant{kBalloonNPerRad};
  RunClosedLoop<S>(params, state, plant, Squeeze<S>(0.6), 0.5, 0.0);
  const S offset_rad = state.offset_rad;
  const S rate_rad_s = state.offset_rate_rad_s;
  ASSERT_NE(rate_rad_s, S(0));  // still moving, so a hold is visible
  const S held_rad = S(kContactRad) + offset_rad;

  const struct {
    S force_n;
    bool valid;
  } bad[] = {{S(0.3), false}, {NaN<S>(), true}, {Inf<S>(), true}, {-Inf<S>(), true}};
  for (const auto& sample : bad) {
    const GraspOutput<S> out = StepGraspController<S>(params, state, Squeeze<S>(0.6),
                                                      sample.force_n, sample.valid, S(kDtS));

    EXPECT_EQ(out.servo_angle_rad, held_rad);
    EXPECT_FALSE(out.regulating);
    EXPECT_EQ(out.force_error_n, S(0));
  }
  EXPECT_EQ(state.offset_rad, offset_rad);
  EXPECT_EQ(state.offset_rate_rad_s, rate_rad_s);
  EXPECT_EQ(state.rejected_inputs, 4u);
}

TYPED_TEST(GraspControllerTest, NonFiniteForceOrDtHoldsTheCommandAndCounts) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  GraspPlant plant{kBalloonNPerRad};
  RunClosedLoop<S>(params, state, plant, Squeeze<S>(0.6), 0.5, 0.0);
  const S offset_rad = state.offset_rad;
  const S rate_rad_s = state.offset_rate_rad_s;
  const S held_rad = S(kContactRad) + offset_rad;

  const struct {
    S force_n;
    S dt_s;
  } bad[] = {{NaN<S>(), S(kDtS)}, {Inf<S>(), S(kDtS)}, {S(0.6), S(0)},
             {S(0.6), S(-kDtS)},  {S(0.6), NaN<S>()},  {S(0.6), Inf<S>()}};
  for (const auto& input : bad) {
    const GraspOutput<S> out =
        StepGraspController<S>(params, state, Squeeze<S>(input.force_n), S(0.3), true, input.dt_s);

    EXPECT_EQ(out.servo_angle_rad, held_rad);
    EXPECT_FALSE(out.regulating);
  }
  EXPECT_EQ(state.offset_rad, offset_rad);
  EXPECT_EQ(state.offset_rate_rad_s, rate_rad_s);
  EXPECT_EQ(state.rejected_inputs, 6u);
}

TYPED_TEST(GraspControllerTest, NonFiniteReferenceAngleHoldsThePreviousCommand) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  GraspPlant plant{kBalloonNPerRad};
  RunClosedLoop<S>(params, state, plant, Squeeze<S>(0.6), 0.5, 0.0);
  const GraspOutput<S> last =
      StepGraspController<S>(params, state, Squeeze<S>(0.6), S(0.3), true, S(kDtS));
  const S offset_rad = state.offset_rad;

  for (const S reference_rad : {NaN<S>(), Inf<S>(), -Inf<S>()}) {
    const GraspOutput<S> out = StepGraspController<S>(
        params, state, Squeeze<S>(0.6, double(reference_rad)), S(0.3), true, S(kDtS));

    EXPECT_EQ(out.servo_angle_rad, last.servo_angle_rad);
    EXPECT_FALSE(out.regulating);
  }
  EXPECT_EQ(state.offset_rad, offset_rad);
  EXPECT_EQ(state.rejected_inputs, 3u);
}

TYPED_TEST(GraspControllerTest, NegativeDesiredForceIsRegulatedAsZero) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  state.last_mode = GraspMode::kForce;

  const GraspOutput<S> out =
      StepGraspController<S>(params, state, Squeeze<S>(-5.0), S(0.2), true, S(kDtS));

  EXPECT_NEAR(out.force_error_n, -0.2, 1e-6);
  EXPECT_NEAR(out.servo_angle_rad, kContactRad - 0.2 / 0.2 * kDtS * kDtS, Tol<S>());
  EXPECT_EQ(state.rejected_inputs, 0u);
}

TYPED_TEST(GraspControllerTest, InvalidParamsNeverRegulate) {
  using S = TypeParam;
  GraspAdmittanceParams<S> zero_mass, nan_damping, inverted_range, nan_open;
  zero_mass.mass = S(0);
  nan_damping.damping = NaN<S>();
  inverted_range.open_angle_rad = S(1.0);
  inverted_range.closed_angle_rad = S(0.5);
  nan_open.open_angle_rad = NaN<S>();

  for (const GraspAdmittanceParams<S>& params :
       {zero_mass, nan_damping, inverted_range, nan_open}) {
    GraspControllerState<S> state;
    state.last_command_rad = S(0.7);

    const GraspOutput<S> out =
        StepGraspController<S>(params, state, Squeeze<S>(0.6), S(0.1), true, S(kDtS));

    EXPECT_FALSE(GraspParamsValid(params));
    EXPECT_FALSE(out.regulating);
    // The open angle where it is a number, else the last command.
    EXPECT_EQ(out.servo_angle_rad,
              std::isfinite(params.open_angle_rad) ? params.open_angle_rad : S(0.7));
    EXPECT_EQ(state.rejected_inputs, 1u);
    EXPECT_EQ(MaxStableGraspDt(params), S(0));
  }
}

TYPED_TEST(GraspControllerTest, StabilityBoundIsAsDocumented) {
  using S = TypeParam;
  GraspAdmittanceParams<S> params;
  GraspAdmittanceParams<S> spring = params;
  spring.stiffness = S(840);

  // K = 0: 2 / c = 2 M / B; K > 0: (√(c² + 4k) − c) / k with c = B/M, k = K/M.
  EXPECT_NEAR(MaxStableGraspDt(params), 2.0 * 0.2 / 65.0, 1e-7);
  EXPECT_NEAR(MaxStableGraspDt(params), 6.2e-3, 1e-4);
  const double c = 65.0 / 0.2, k = 840.0 / 0.2;
  EXPECT_NEAR(MaxStableGraspDt(spring), (std::sqrt(c * c + 4.0 * k) - c) / k, 1e-7);
  EXPECT_NEAR(MaxStableGraspDt(spring), 5.9e-3, 1e-4);
}

TYPED_TEST(GraspControllerTest, OutputIsAlwaysFiniteAndInRange) {
  using S = TypeParam;
  const GraspAdmittanceParams<S> params;
  GraspControllerState<S> state;
  const std::array<S, 10> values = {NaN<S>(), Inf<S>(), -Inf<S>(), S(-1),    S(0),
                                    S(0.3),   S(0.8),   S(1e30),   S(-1e30), S(1e-3)};
  const std::array<GraspMode, 3> modes = {GraspMode::kOpen, GraspMode::kForce,
                                          static_cast<GraspMode>(7)};
  std::mt19937 rng(42);
  const auto pick = [&rng](const auto& options) {
    return options[std::uniform_int_distribution<std::size_t>(0, options.size() - 1)(rng)];
  };

  int non_finite = 0, out_of_range = 0;
  for (int i = 0; i < 20'000; ++i) {
    const GraspCommand<S> command{i % 50 < 45 ? GraspMode::kForce : pick(modes), pick(values),
                                  pick(values)};
    const S dt_s = i % 3 == 0 ? pick(values) : S(kDtS);
    const GraspOutput<S> out =
        StepGraspController<S>(params, state, command, pick(values), i % 7 != 0, dt_s);

    const bool finite = std::isfinite(out.servo_angle_rad) && std::isfinite(out.force_error_n) &&
                        std::isfinite(state.offset_rad) && std::isfinite(state.offset_rate_rad_s);
    non_finite += finite ? 0 : 1;
    out_of_range += out.servo_angle_rad >= S(0) && out.servo_angle_rad <= S(1.6) ? 0 : 1;
  }

  EXPECT_EQ(non_finite, 0);
  EXPECT_EQ(out_of_range, 0);
  EXPECT_GT(state.rejected_inputs, 0u);
}

}  // namespace
}  // namespace hilrig::dut_fw
