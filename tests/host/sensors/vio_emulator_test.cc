#include "host/sensors/vio_emulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hilrig::host {
namespace {

constexpr std::int64_t kTickNs = 1'000'000;

// A body moving at a constant velocity and yaw rate, so a stale or mistimed pose shows.
RigidBodyState TruthAt(std::int64_t time_ns) {
  const double t = time_ns * 1e-9;
  RigidBodyState body;
  body.position_m = {1.0 + 0.5 * t, -0.3 * t, 2.0};
  body.orientation = Eigen::AngleAxisd(0.2 * t, Eigen::Vector3d::UnitZ());
  return body;
}

struct Delivered {
  VioPose pose;
  std::int64_t tick_ns;
};

std::vector<Delivered> RunTicks(const VioParams& params, VioState& state, int ticks) {
  std::vector<Delivered> delivered;
  std::vector<VioPose> out;
  for (int i = 0; i < ticks; ++i) {
    const std::int64_t now = i * kTickNs;
    CaptureVio(params, state, TruthAt(now), now);
    out.clear();
    DeliverVio(state, now, out);
    for (const VioPose& pose : out) delivered.push_back({pose, now});
  }
  return delivered;
}

VioParams NoiseFree() {
  VioParams params;
  params.noise_enabled = false;
  return params;
}

TEST(VioEmulatorTest, LatencyIsHonoredExactly) {
  const VioParams params = NoiseFree();
  VioState state;
  const auto delivered = RunTicks(params, state, 1000);
  ASSERT_FALSE(delivered.empty());
  for (const Delivered& d : delivered) {
    EXPECT_EQ(d.pose.delivery_time_ns - d.pose.capture_time_ns, 30'000'000);
    EXPECT_EQ(d.tick_ns, d.pose.delivery_time_ns);  // not a tick earlier, not a tick later
  }
}

TEST(VioEmulatorTest, NothingIsDeliveredBeforeItsTime) {
  const VioParams params = NoiseFree();
  VioState state;
  CaptureVio(params, state, TruthAt(0), 0);
  std::vector<VioPose> out;
  EXPECT_EQ(DeliverVio(state, 29'999'999, out), 0u);
  EXPECT_EQ(DeliverVio(state, 30'000'000, out), 1u);
  EXPECT_EQ(out.size(), 1u);
}

TEST(VioEmulatorTest, RateIsHonoredWithoutDrift) {
  const VioParams params = NoiseFree();
  VioState state;
  const auto delivered = RunTicks(params, state, 10'000 + 30);  // 10 s plus the latency
  ASSERT_EQ(delivered.size(), 300u);
  for (std::size_t i = 0; i < delivered.size(); ++i) {
    EXPECT_EQ(delivered[i].pose.sequence, i);
    // Frame i is taken on the first tick at or after its scheduled time i * 33.333333 ms.
    const std::int64_t scheduled = static_cast<std::int64_t>(i) * 33'333'333;
    EXPECT_GE(delivered[i].pose.capture_time_ns, scheduled);
    EXPECT_LT(delivered[i].pose.capture_time_ns, scheduled + kTickNs);
  }
}

TEST(VioEmulatorTest, NoiseFreePoseEqualsTruthAtCaptureTime) {
  const VioParams params = NoiseFree();
  VioState state;
  const auto delivered = RunTicks(params, state, 1000);
  ASSERT_FALSE(delivered.empty());
  for (const Delivered& d : delivered) {
    const RigidBodyState truth = TruthAt(d.pose.capture_time_ns);
    EXPECT_EQ(d.pose.position_m, truth.position_m);
    EXPECT_EQ(d.pose.orientation.coeffs(), truth.orientation.coeffs());
  }
}

TEST(VioEmulatorTest, PositionAndAttitudeNoiseMatchSigma) {
  const VioParams params;
  VioState state;
  state.rng = RandomStream::FromSeed(4, StreamId::kVio);
  const RigidBodyState truth = TruthAt(0);
  std::vector<VioPose> out;
  double position_sq = 0.0, attitude_sq = 0.0;
  constexpr int kCaptures = 20000;
  for (int i = 0; i < kCaptures; ++i) {
    const std::int64_t now = state.next_capture_ns;
    CaptureVio(params, state, truth, now);
    out.clear();
    DeliverVio(state, now + VioLatencyNs(params), out);
    ASSERT_EQ(out.size(), 1u);
    position_sq += (out[0].position_m - truth.position_m).squaredNorm();
    attitude_sq += std::pow(out[0].orientation.angularDistance(truth.orientation), 2);
  }
  EXPECT_NEAR(std::sqrt(position_sq / (3 * kCaptures)) / 0.003, 1.0, 0.05);
  EXPECT_NEAR(std::sqrt(attitude_sq / (3 * kCaptures)) / 0.002, 1.0, 0.05);
}

TEST(VioEmulatorTest, SkippedPeriodsAreDroppedNotBurst) {
  const VioParams params = NoiseFree();
  VioState state;
  CaptureVio(params, state, TruthAt(0), 0);
  CaptureVio(params, state, TruthAt(500'000'000), 500'000'000);  // caller jumped 0.5 s
  CaptureVio(params, state, TruthAt(500'000'000), 500'000'000);
  EXPECT_EQ(state.in_flight.size(), 2u);
  EXPECT_EQ(state.next_capture_ns, 16 * 33'333'333);  // back on the schedule grid
}

}  // namespace
}  // namespace hilrig::host
