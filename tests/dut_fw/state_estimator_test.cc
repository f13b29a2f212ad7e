#include "dut_fw/state_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class StateEstimatorTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(StateEstimatorTest, Scalars);

constexpr double kG = 9.81;
constexpr std::int64_t kImuPeriodNs = 1'000'000;   // 1 kHz
constexpr std::int64_t kVioPeriodNs = 33'333'333;  // 30 Hz
constexpr std::int64_t kVioLatencyNs = 40'000'000;

template <typename S>
EstimatorGains<S> Gains() {
  EstimatorGains<S> g = EstimatorGainsWithPoles<S>(S(0.9));
  g.gravity_m_s2 = S(kG);
  return g;
}

// Ground truth of a body moving at constant velocity and constant orientation (zero acceleration,
// zero rate), seen through an IMU with constant biases and a VIO with a fixed latency.
struct Truth {
  Eigen::Vector3d position0_m = Eigen::Vector3d(0.5, -0.3, 1.0);
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();

  Eigen::Vector3d PositionAt(std::int64_t t_ns) const {
    return position0_m + velocity_m_s * (double(t_ns) * 1e-9);
  }
};

struct PendingPose {
  std::int64_t capture_ns;
  Eigen::Vector3d position_m;
  Eigen::Quaterniond orientation;
};

// Runs IMU at 1 kHz and VIO at 30 Hz (delivered kVioLatencyNs after capture) from t = 0 to end_ns;
// calls check(t_ns, state) after every IMU sample.
template <typename S, int N, typename Check>
void Run(const Truth& truth, EstimatorState<S, N>& state, std::int64_t end_ns, Check check) {
  const EstimatorGains<S> gains = Gains<S>();
  std::deque<PendingPose> pending;
  std::int64_t next_capture_ns = 0;
  const Eigen::Vector3d specific_force =
      truth.orientation.conjugate() * Eigen::Vector3d(0, 0, kG) + truth.accel_bias_m_s2;
  for (std::int64_t t = 0; t <= end_ns; t += kImuPeriodNs) {
    if (t >= next_capture_ns) {
      pending.push_back({next_capture_ns, truth.PositionAt(next_capture_ns), truth.orientation});
      next_capture_ns += kVioPeriodNs;
    }
    PropagateImu<S, N>(gains, state, truth.gyro_bias_rad_s.cast<S>(), specific_force.cast<S>(), t);
    while (!pending.empty() && pending.front().capture_ns + kVioLatencyNs <= t) {
      const PendingPose& p = pending.front();
      CorrectWithVio<S, N>(gains, state, p.position_m.cast<S>(), p.orientation.cast<S>(),
                           p.capture_ns);
      pending.pop_front();
    }
    check(t, state);
  }
}

TYPED_TEST(StateEstimatorTest, StaysUninitializedUntilTheFirstPose) {
  using S = TypeParam;
  EstimatorState<S> state;

  for (int i = 0; i < 10; ++i) {
    PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)),
                    i * kImuPeriodNs);
  }
  const bool before = state.initialized;
  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>(S(1), S(2), S(3)), Quat<S>::Identity(),
                    5 * kImuPeriodNs);

  EXPECT_FALSE(before);
  EXPECT_TRUE(state.initialized);
  EXPECT_EQ(state.position_m, Vec3<S>(S(1), S(2), S(3)));
  EXPECT_EQ(state.time_ns, 9 * kImuPeriodNs);
  EXPECT_EQ(state.history_count, 1);
}

TYPED_TEST(StateEstimatorTest, StaticConvergesAndEstimatesBiases) {
  using S = TypeParam;
  Truth truth;
  truth.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()) *
                                         Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()));
  truth.gyro_bias_rad_s = Eigen::Vector3d(0.01, -0.02, 0.015);
  truth.accel_bias_m_s2 = Eigen::Vector3d(0.1, -0.05, 0.2);
  EstimatorState<S> state;

  Run<S>(truth, state, 30'000'000'000, [](std::int64_t, const EstimatorState<S>&) {});

  EXPECT_NEAR(state.gyro_bias_rad_s.x(), 0.01, 2e-4);
  EXPECT_NEAR(state.gyro_bias_rad_s.y(), -0.02, 2e-4);
  EXPECT_NEAR(state.gyro_bias_rad_s.z(), 0.015, 2e-4);
  EXPECT_NEAR(state.accel_bias_m_s2.x(), 0.1, 2e-3);
  EXPECT_NEAR(state.accel_bias_m_s2.y(), -0.05, 2e-3);
  EXPECT_NEAR(state.accel_bias_m_s2.z(), 0.2, 2e-3);
  EXPECT_LT((state.position_m.template cast<double>() - truth.position0_m).norm(), 1e-3);
  EXPECT_LT(state.velocity_m_s.norm(), 1e-3);
  EXPECT_LT(state.orientation.template cast<double>().angularDistance(truth.orientation), 1e-3);
  EXPECT_EQ(state.rejected_samples, 0u);
}

TYPED_TEST(StateEstimatorTest, DelayedVioDuringConstantVelocityIsCompensated) {
  using S = TypeParam;
  Truth truth;
  truth.velocity_m_s = Eigen::Vector3d(1.0, 0.5, -0.2);
  truth.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  EstimatorState<S> state;
  double max_error_late_m = 0.0;

  Run<S>(truth, state, 10'000'000'000, [&](std::int64_t t, const EstimatorState<S>& s) {
    if (t >= 8'000'000'000) {
      const double e = (s.position_m.template cast<double>() - truth.PositionAt(t)).norm();
      max_error_late_m = std::max(max_error_late_m, e);
    }
  });

  // v * latency = 4.6 cm; the history-compensated estimate is ~100x better.
  EXPECT_LT(max_error_late_m, 5e-4);
  EXPECT_NEAR(state.velocity_m_s.x(), 1.0, 1e-3);
  EXPECT_NEAR(state.velocity_m_s.y(), 0.5, 1e-3);
  EXPECT_NEAR(state.velocity_m_s.z(), -0.2, 1e-3);
}

// Common start: initialized at the origin, 100 ms of level, static IMU data.
template <typename S>
EstimatorState<S> Initialized() {
  EstimatorState<S> state;
  PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)), 0);
  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>::Zero(), Quat<S>::Identity(), 0);
  for (int i = 1; i <= 100; ++i) {
    PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)),
                    i * kImuPeriodNs);
  }
  return state;
}

TYPED_TEST(StateEstimatorTest, NanImuSampleIsRejectedAndCounted) {
  using S = TypeParam;
  EstimatorState<S> state = Initialized<S>();
  const S nan = std::numeric_limits<S>::quiet_NaN();

  PropagateImu<S>(Gains<S>(), state, Vec3<S>(nan, S(0), S(0)), Vec3<S>(S(0), S(0), S(kG)),
                  101 * kImuPeriodNs);
  PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(),
                  Vec3<S>(S(0), std::numeric_limits<S>::infinity(), S(kG)), 102 * kImuPeriodNs);

  EXPECT_EQ(state.rejected_samples, 2u);
  EXPECT_EQ(state.rejected_non_finite, 2u);
  EXPECT_EQ(state.time_ns, 100 * kImuPeriodNs);
  EXPECT_TRUE(AllFinite(state.position_m));
  EXPECT_TRUE(AllFinite(state.orientation));
}

TYPED_TEST(StateEstimatorTest, NanOrDegenerateVioPoseIsRejectedAndCounted) {
  using S = TypeParam;
  EstimatorState<S> state = Initialized<S>();
  const S nan = std::numeric_limits<S>::quiet_NaN();

  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>(S(0), nan, S(0)), Quat<S>::Identity(),
                    60 * kImuPeriodNs);
  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>::Zero(), Quat<S>(S(0), S(0), S(0), S(0)),
                    60 * kImuPeriodNs);

  EXPECT_EQ(state.rejected_samples, 2u);
  EXPECT_EQ(state.rejected_non_finite, 2u);
  EXPECT_TRUE(AllFinite(state.position_m));
}

TYPED_TEST(StateEstimatorTest, VioOlderThanTheHistoryIsRejected) {
  using S = TypeParam;
  EstimatorState<S, 16> state;
  PropagateImu<S, 16>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)), 0);
  CorrectWithVio<S, 16>(Gains<S>(), state, Vec3<S>::Zero(), Quat<S>::Identity(), 0);
  for (int i = 1; i <= 100; ++i) {
    PropagateImu<S, 16>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)),
                        i * kImuPeriodNs);
  }

  // The 16-entry ring covers 85..100 ms; a pose captured at 50 ms is too old.
  CorrectWithVio<S, 16>(Gains<S>(), state, Vec3<S>(S(1), S(0), S(0)), Quat<S>::Identity(),
                        50 * kImuPeriodNs);

  EXPECT_EQ(state.rejected_stale_vio, 1u);
  EXPECT_EQ(state.rejected_samples, 1u);
  EXPECT_EQ(state.position_m, Vec3<S>::Zero());
}

TYPED_TEST(StateEstimatorTest, ImuTimeThatDoesNotAdvanceIsRejected) {
  using S = TypeParam;
  EstimatorState<S> state = Initialized<S>();
  const Vec3<S> kicking(S(5), S(0), S(kG));

  PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), kicking, 100 * kImuPeriodNs);
  PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), kicking, 90 * kImuPeriodNs);

  EXPECT_EQ(state.rejected_out_of_order, 2u);
  EXPECT_EQ(state.rejected_samples, 2u);
  EXPECT_EQ(state.velocity_m_s, Vec3<S>::Zero());
}

TYPED_TEST(StateEstimatorTest, PositionInnovationIsAppliedOnceAcrossTheHistory) {
  using S = TypeParam;
  EstimatorState<S> state = Initialized<S>();
  const EstimatorGains<S> gains = Gains<S>();

  // Two poses captured at 60 and 61 ms, both 10 cm off in x.
  CorrectWithVio<S>(gains, state, Vec3<S>(S(0.1), S(0), S(0)), Quat<S>::Identity(),
                    60 * kImuPeriodNs);
  const S after_first = state.position_m.x();
  CorrectWithVio<S>(gains, state, Vec3<S>(S(0.1), S(0), S(0)), Quat<S>::Identity(),
                    61 * kImuPeriodNs);
  const S after_second = state.position_m.x();

  // First: α·0.1 plus the velocity correction carried over the 40 ms since capture.
  const double alpha = gains.position_gain;
  const double beta = gains.velocity_gain;
  const double dv1 = beta * 0.1 / 0.060;  // 60 ms since the seed pose
  const double period = 0.5 / 30.0;       // 1 ms spacing, clamped to half the nominal period
  EXPECT_NEAR(after_first, alpha * 0.1 + dv1 * 0.040, 1e-5);
  // Second: the history at 61 ms already holds the first correction, so only the remainder counts.
  const double p_then = alpha * 0.1 + dv1 * 0.001;
  const double innovation = 0.1 - p_then;
  EXPECT_NEAR(after_second, after_first + alpha * innovation + beta * innovation / period * 0.039,
              1e-5);
}

TYPED_TEST(StateEstimatorTest, PoseCapturedBeforeInitializationTimeIsStillUsed) {
  using S = TypeParam;
  EstimatorState<S> state;
  for (int i = 0; i <= 40; ++i) {
    PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)),
                    i * kImuPeriodNs);
  }
  // First pose captured at 0, delivered at 40 ms; second captured at 33 ms, i.e. before "now".
  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>::Zero(), Quat<S>::Identity(), 0);
  for (int i = 41; i <= 73; ++i) {
    PropagateImu<S>(Gains<S>(), state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)),
                    i * kImuPeriodNs);
  }

  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>(S(0.1), S(0), S(0)), Quat<S>::Identity(),
                    33 * kImuPeriodNs);

  EXPECT_EQ(state.rejected_samples, 0u);
  EXPECT_GT(state.position_m.x(), 0.02);
}

TYPED_TEST(StateEstimatorTest, AttitudeInnovationRotatesTowardThePose) {
  using S = TypeParam;
  EstimatorState<S> state = Initialized<S>();
  const Quat<S> yawed = QuatExp<S>(Vec3<S>(S(0), S(0), S(0.1)));

  CorrectWithVio<S>(Gains<S>(), state, Vec3<S>::Zero(), yawed, 60 * kImuPeriodNs);

  const Vec3<S> body_x = state.orientation * Vec3<S>::UnitX();
  const double gain = Gains<S>().attitude_gain;
  EXPECT_NEAR(std::atan2(body_x.y(), body_x.x()), gain * 2.0 * std::sin(0.05), 1e-5);
  EXPECT_LT(state.gyro_bias_rad_s.z(), 0.0);  // the estimate lagged, so its rate is raised
}

}  // namespace
}  // namespace hilrig::dut_fw
