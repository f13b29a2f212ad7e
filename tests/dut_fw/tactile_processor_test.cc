#include "dut_fw/tactile_processor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "dut_fw/mlx90393.h"

namespace hilrig::dut_fw {
namespace {

template <typename S>
class TactileProcessorTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(TactileProcessorTest, Scalars);

constexpr std::int64_t kPeriodNs = 20'000'000;  // 50 Hz
constexpr Mlx90393Setting kChip{7, 0};
const Vec3<double> kEarthWorldT(0.0, 2.4e-5, -4.16e-5);
const Vec3<double> kFilmT(0.0, 0.0, 3.5e-3);  // no-load film field at every chip

Mat3<double> Rotation(double angle_rad, const Vec3<double>& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// What the chip sends for `field_t`: quantized to its LSB and encoded, as the device emulator does.
std::array<std::uint16_t, 3> Encode(const Vec3<double>& field_t) {
  const Vec3<double> lsb_t = LsbTesla<double>(kChip);
  std::array<std::uint16_t, 3> codes{};
  for (int axis = 0; axis < 3; ++axis) {
    codes[axis] =
        EncodeCode(std::int32_t(std::lround(field_t[axis] / lsb_t[axis])), kChip.resolution).code;
  }
  return codes;
}

// Six sensors around the inner wall of the frame, each tilted differently, and a reference board
// mounted at yet another angle; everything the processor needs to know about them.
struct Airframe {
  std::array<Mat3<double>, 6> body_from_sensor;
  Mat3<double> body_from_reference = Rotation(0.7, {0.2, 1.0, -0.4});

  Airframe() {
    for (int i = 0; i < 6; ++i) {
      body_from_sensor[i] = Rotation(i * EIGEN_PI / 3.0, Vec3<double>::UnitZ()) *
                            Rotation(EIGEN_PI / 2.0 + 0.1 * i, Vec3<double>::UnitY());
    }
  }

  template <typename S>
  TactileProcessorParams<S> Params() const {
    TactileProcessorParams<S> params;
    params.film = FilmConstants<S>::Published();
    params.chip_setting = kChip;
    params.zeroing_samples = 10;
    for (int i = 0; i < 6; ++i) {
      TactileNodeConfig<S>& node = params.nodes[i];
      node.node_id = std::uint8_t(i + 1);
      node.rotation_sensor_from_reference =
          (body_from_sensor[i].transpose() * body_from_reference).cast<S>();
      node.rotation_body_from_sensor = body_from_sensor[i].cast<S>();
      node.contact_normal_sensor = Vec3<S>::UnitZ();
      node.gain_a = Vec3<S>(S(20), S(20), S(30));
    }
    return params;
  }

  Vec3<double> SensorField(int i, const Mat3<double>& world_from_body) const {
    return kFilmT + (world_from_body * body_from_sensor[i]).transpose() * kEarthWorldT;
  }
  Vec3<double> ReferenceField(const Mat3<double>& world_from_body) const {
    return (world_from_body * body_from_reference).transpose() * kEarthWorldT;
  }
};

// One 50 Hz tick of the bus at an attitude: the reference sample, then every tactile node's.
template <typename S>
void Tick(const Airframe& airframe, const TactileProcessorParams<S>& params,
          TactileProcessorState<S>& state, const Mat3<double>& world_from_body, int tick) {
  const std::int64_t time_ns = tick * kPeriodNs;
  const std::uint8_t sequence = std::uint8_t(tick);
  OnReferenceSample(params, state, Encode(airframe.ReferenceField(world_from_body)), sequence,
                    false, time_ns);
  for (int i = 0; i < 6; ++i) {
    OnTactileSample(params, state, std::uint8_t(i + 1),
                    Encode(airframe.SensorField(i, world_from_body)), sequence, false, time_ns);
  }
}

// Ticks 0 .. zeroing_samples - 1 at `world_from_body`: exactly the no-load window.
template <typename S>
void Zero(const Airframe& airframe, const TactileProcessorParams<S>& params,
          TactileProcessorState<S>& state, const Mat3<double>& world_from_body) {
  for (int tick = 0; tick < int(params.zeroing_samples); ++tick) {
    Tick(airframe, params, state, world_from_body, tick);
  }
}

TYPED_TEST(TactileProcessorTest, ZeroingCompletesAfterTheWindowAndNoLoadForceIsZero) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const Mat3<double> attitude = Rotation(0.3, {1.0, -0.5, 0.2});
  for (int tick = 0; tick + 1 < int(params.zeroing_samples); ++tick) {
    Tick(airframe, params, state, attitude, tick);
  }
  const TactileSummary<S> before = SummarizeTactile(params, state, 8 * kPeriodNs);

  Tick(airframe, params, state, attitude, int(params.zeroing_samples) - 1);
  const TactileSummary<S> after = SummarizeTactile(params, state, 9 * kPeriodNs);

  EXPECT_FALSE(before.ready);
  EXPECT_EQ(before.nodes_contributing, 0);
  EXPECT_EQ(before.external_force_body_n, Vec3<S>::Zero());
  EXPECT_TRUE(after.ready);
  EXPECT_EQ(after.nodes_contributing, 6);
  EXPECT_LT(after.max_force_magnitude_n, S(1e-4));
  for (const TactileNodeState<S>& node : state.nodes) {
    EXPECT_TRUE(node.zeroed);
    EXPECT_EQ(node.zero.count, params.zeroing_samples);
    EXPECT_EQ(node.last_status, DecodeStatus::kOk);
  }
}

TYPED_TEST(TactileProcessorTest, CompensationHoldsNoLoadForceAcrossAttitudesAblationDoesNot) {
  using S = TypeParam;
  const Airframe airframe;
  TactileProcessorParams<S> compensated = airframe.Params<S>();
  TactileProcessorParams<S> raw = compensated;
  raw.compensation_enabled = false;
  TactileProcessorState<S> compensated_state, raw_state;
  const Mat3<double> level = Mat3<double>::Identity();
  Zero(airframe, compensated, compensated_state, level);
  Zero(airframe, raw, raw_state, level);
  const int tick = int(compensated.zeroing_samples);
  const Mat3<double> banked = Rotation(2.0, {0.6, -1.0, 0.3});

  Tick(airframe, compensated, compensated_state, banked, tick);
  Tick(airframe, raw, raw_state, banked, tick);

  // Quantization of sensor and reference (~0.3 µT after rotation) bounds the residual; the sensor
  // spec is 0.05 N.
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT(compensated_state.nodes[i].force_sensor_n.norm(), S(0.01)) << i;
    EXPECT_GT(raw_state.nodes[i].force_sensor_n.norm(), S(0.1)) << i;
  }
  const TactileSummary<S> summary =
      SummarizeTactile(compensated, compensated_state, tick * kPeriodNs);
  EXPECT_TRUE(summary.ready);
  EXPECT_LT(summary.external_force_body_n.norm(), S(0.03));
}

TYPED_TEST(TactileProcessorTest, StaleReferenceFlagsTheSampleAndKeepsTheForce) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const Mat3<double> level = Mat3<double>::Identity();
  Zero(airframe, params, state, level);
  const Vec3<S> force_before = state.nodes[0].force_sensor_n;
  const std::int64_t late_ns =
      state.reference_time_ns + params.max_reference_age_ns + 1;  // no reference since

  OnTactileSample(params, state, 1, Encode(airframe.SensorField(0, level)),
                  std::uint8_t(params.zeroing_samples), false, late_ns);

  const TactileNodeState<S>& node = state.nodes[0];
  EXPECT_TRUE(node.last_reference_stale);
  EXPECT_EQ(node.last_status, DecodeStatus::kNonFiniteInput);
  EXPECT_STREQ(TactileNodeStatusName(node), "stale_reference");
  EXPECT_EQ(node.flagged, 1u);
  EXPECT_EQ(node.stale_reference, 1u);
  EXPECT_EQ(node.force_sensor_n, force_before);
  EXPECT_LT(node.last_force_ns, late_ns);
}

TYPED_TEST(TactileProcessorTest, NoReferenceYetIsStaleUnlessCompensationIsOff) {
  using S = TypeParam;
  const Airframe airframe;
  TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorParams<S> raw = params;
  raw.compensation_enabled = false;
  TactileProcessorState<S> state, raw_state;
  const auto codes = Encode(airframe.SensorField(0, Mat3<double>::Identity()));

  OnTactileSample(params, state, 1, codes, 0, false, 0);
  OnTactileSample(raw, raw_state, 1, codes, 0, false, 0);

  EXPECT_EQ(state.nodes[0].stale_reference, 1u);
  EXPECT_EQ(state.nodes[0].zero.count, 0u);
  EXPECT_EQ(raw_state.nodes[0].stale_reference, 0u);
  EXPECT_EQ(raw_state.nodes[0].zero.count, 1u);
}

TYPED_TEST(TactileProcessorTest, SequenceWrapIsNotAGap) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const auto tactile = Encode(airframe.SensorField(0, Mat3<double>::Identity()));
  const auto reference = Encode(airframe.ReferenceField(Mat3<double>::Identity()));

  int tick = 0;
  for (std::uint8_t sequence :
       {std::uint8_t(254), std::uint8_t(255), std::uint8_t(0), std::uint8_t(1)}) {
    OnReferenceSample(params, state, reference, sequence, false, tick * kPeriodNs);
    OnTactileSample(params, state, 1, tactile, sequence, false, tick * kPeriodNs);
    ++tick;
  }

  EXPECT_EQ(state.nodes[0].sequence_gaps, 0u);
  EXPECT_EQ(state.nodes[0].samples, 4u);
  EXPECT_EQ(state.reference_sequence_gaps, 0u);
  EXPECT_EQ(state.reference_samples, 4u);
}

TYPED_TEST(TactileProcessorTest, SkippedCountersCountTheMissedSamples) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const auto tactile = Encode(airframe.SensorField(0, Mat3<double>::Identity()));
  const auto reference = Encode(airframe.ReferenceField(Mat3<double>::Identity()));

  OnReferenceSample(params, state, reference, 254, false, 0);
  OnTactileSample(params, state, 1, tactile, 10, false, 0);
  OnReferenceSample(params, state, reference, 1, false, kPeriodNs);  // 255, 0 missed
  OnTactileSample(params, state, 1, tactile, 14, false, kPeriodNs);  // 11, 12, 13 missed

  EXPECT_EQ(state.reference_sequence_gaps, 2u);
  EXPECT_EQ(state.nodes[0].sequence_gaps, 3u);
  EXPECT_EQ(state.nodes[0].samples, 2u);
}

TYPED_TEST(TactileProcessorTest, DuplicateSequenceIsCountedAndNotDecodedTwice) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const Mat3<double> level = Mat3<double>::Identity();
  const auto tactile = Encode(airframe.SensorField(0, level));
  OnReferenceSample(params, state, Encode(airframe.ReferenceField(level)), 5, false, 0);
  OnTactileSample(params, state, 1, tactile, 5, false, 0);

  OnReferenceSample(params, state, Encode(airframe.ReferenceField(level)), 5, false, kPeriodNs);
  OnTactileSample(params, state, 1, tactile, 5, false, kPeriodNs);

  const TactileNodeState<S>& node = state.nodes[0];
  EXPECT_EQ(node.samples, 1u);
  EXPECT_EQ(node.duplicates, 1u);
  EXPECT_EQ(node.sequence_gaps, 0u);
  EXPECT_EQ(node.zero.count, 1u);
  EXPECT_EQ(node.last_sample_ns, 0);
  EXPECT_EQ(state.reference_duplicates, 1u);
  EXPECT_EQ(state.reference_time_ns, 0);
}

TYPED_TEST(TactileProcessorTest, NodeReportedSaturationIsFlaggedAndKeepsTheForce) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const Mat3<double> level = Mat3<double>::Identity();
  Zero(airframe, params, state, level);
  const int tick = int(params.zeroing_samples);
  const Vec3<S> force_before = state.nodes[2].force_sensor_n;
  OnReferenceSample(params, state, Encode(airframe.ReferenceField(level)), std::uint8_t(tick),
                    false, tick * kPeriodNs);

  OnTactileSample(params, state, 3, Encode(airframe.SensorField(2, level)), std::uint8_t(tick),
                  true, tick * kPeriodNs);

  const TactileNodeState<S>& node = state.nodes[2];
  EXPECT_EQ(node.last_status, DecodeStatus::kSaturated);
  EXPECT_FALSE(node.last_reference_stale);
  EXPECT_EQ(node.flagged, 1u);
  EXPECT_EQ(node.force_sensor_n, force_before);
}

TYPED_TEST(TactileProcessorTest, CodeAtARailIsFlaggedAndSkippedDuringZeroing) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const Mat3<double> level = Mat3<double>::Identity();
  std::array<std::uint16_t, 3> clipped = Encode(airframe.SensorField(0, level));
  clipped[2] = EncodeCode(40000, kChip.resolution).code;
  OnReferenceSample(params, state, Encode(airframe.ReferenceField(level)), 0, false, 0);

  OnTactileSample(params, state, 1, clipped, 0, false, 0);

  EXPECT_EQ(state.nodes[0].last_status, DecodeStatus::kSaturated);
  EXPECT_EQ(state.nodes[0].flagged, 1u);
  EXPECT_EQ(state.nodes[0].zero.count, 0u);
  EXPECT_EQ(state.nodes[0].zero.rejected, 1u);
}

TYPED_TEST(TactileProcessorTest, UnknownNodeIsCountedAndIgnored) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> params = airframe.Params<S>();
  TactileProcessorState<S> state;
  const auto codes = Encode(kFilmT);

  OnTactileSample(params, state, tactile_bus::kReferenceNodeId, codes, 0, false, 0);
  OnTactileSample(params, state, 0, codes, 0, false, 0);
  OnTactileSample(params, state, 42, codes, 0, false, 0);

  EXPECT_EQ(state.unknown_nodes, 3u);
  for (const TactileNodeState<S>& node : state.nodes) {
    EXPECT_FALSE(node.has_sample);
    EXPECT_FALSE(node.has_sequence);
  }
}

// Sets a node as if it had been zeroed and had just decoded `force_sensor_n`.
template <typename S>
void SetForce(TactileProcessorState<S>& state, int slot, const Vec3<S>& force_sensor_n,
              std::int64_t time_ns) {
  TactileNodeState<S>& node = state.nodes[slot];
  node.zeroed = true;
  node.has_force = true;
  node.force_sensor_n = force_sensor_n;
  node.last_force_ns = time_ns;
}

TYPED_TEST(TactileProcessorTest, ExternalForceRotatesIntoBodyAndGraspSumsAbsoluteNormalParts) {
  using S = TypeParam;
  TactileProcessorParams<S> params;
  TactileProcessorState<S> state;
  Vec3<double> expected_body = Vec3<double>::Zero();
  double expected_grasp = 0.0;
  for (int i = 0; i < 6; ++i) {
    const Mat3<double> body_from_sensor = Rotation(0.5 + i, {1.0, 0.3 * i, -0.7});
    const Vec3<double> normal = Vec3<double>(0.2 * i, -0.3, 1.0).normalized();
    // Alternating signs of the normal part: the grasp force must add magnitudes, not cancel.
    const Vec3<double> force_n(0.1 * i, -0.2, (i % 2 ? -1.0 : 1.0) * (0.3 + 0.1 * i));
    params.nodes[i].node_id = std::uint8_t(i + 1);
    params.nodes[i].rotation_body_from_sensor = body_from_sensor.cast<S>();
    params.nodes[i].contact_normal_sensor = normal.cast<S>();
    SetForce<S>(state, i, force_n.cast<S>(), 0);
    expected_body += body_from_sensor * force_n;
    expected_grasp += std::abs(force_n.dot(normal));
  }

  const TactileSummary<S> summary = SummarizeTactile(params, state, 0);

  const S tolerance = S(64) * std::numeric_limits<S>::epsilon();
  EXPECT_TRUE(summary.ready);
  EXPECT_EQ(summary.nodes_contributing, 6);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(summary.external_force_body_n[axis], S(expected_body[axis]), tolerance);
  }
  EXPECT_NEAR(summary.grasp_force_n, S(expected_grasp), tolerance);
}

TYPED_TEST(TactileProcessorTest, SilentNodeDropsOutOfTheSumsAndClearsReady) {
  using S = TypeParam;
  TactileProcessorParams<S> params;
  TactileProcessorState<S> state;
  const std::int64_t silent_since_ns = 1'000'000'000;
  const std::int64_t now_ns = silent_since_ns + params.max_sample_age_ns + 1;
  for (int i = 0; i < 6; ++i) {
    params.nodes[i].node_id = std::uint8_t(i + 1);
    const std::int64_t last_ns = i == 4 ? silent_since_ns : now_ns;
    SetForce<S>(state, i, Vec3<S>(S(0), S(0), S(1)), last_ns);
  }

  const TactileSummary<S> at_limit =
      SummarizeTactile(params, state, silent_since_ns + params.max_sample_age_ns);
  const TactileSummary<S> past_limit = SummarizeTactile(params, state, now_ns);

  EXPECT_TRUE(at_limit.ready);
  EXPECT_EQ(at_limit.nodes_contributing, 6);
  EXPECT_FALSE(past_limit.ready);
  EXPECT_EQ(past_limit.nodes_contributing, 5);
  EXPECT_EQ(past_limit.external_force_body_n.z(), S(5));
  EXPECT_EQ(past_limit.grasp_force_n, S(5));
}

// The summary may be kept until the first fresh node goes stale: it is the same at that moment and
// different one nanosecond later.
TYPED_TEST(TactileProcessorTest, SummaryStaysValidUntilTheFirstFreshNodeGoesStale) {
  using S = TypeParam;
  TactileProcessorParams<S> params;
  TactileProcessorState<S> state;
  const std::int64_t now_ns = 1'000'000'000;
  for (int i = 0; i < 6; ++i) {
    params.nodes[i].node_id = std::uint8_t(i + 1);
    SetForce<S>(state, i, Vec3<S>(S(0), S(0), S(1)), now_ns - 1'000'000 * (i + 1));
  }
  // Node 6 (slot 5) sampled 6 ms ago goes stale first.
  const std::int64_t until = TactileSummaryValidUntil(params, state, now_ns);
  EXPECT_EQ(until, now_ns - 6'000'000 + params.max_sample_age_ns);
  EXPECT_EQ(SummarizeTactile(params, state, until).nodes_contributing, 6);
  EXPECT_EQ(SummarizeTactile(params, state, until + 1).nodes_contributing, 5);
}

TYPED_TEST(TactileProcessorTest, SummaryValidityIgnoresStaleNodesAndDistrustsFutureStamps) {
  using S = TypeParam;
  TactileProcessorParams<S> params;
  TactileProcessorState<S> state;
  const std::int64_t now_ns = 1'000'000'000;
  for (int i = 0; i < 6; ++i) params.nodes[i].node_id = std::uint8_t(i + 1);
  SetForce<S>(state, 0, Vec3<S>(S(0), S(0), S(1)), now_ns - 10 * params.max_sample_age_ns);
  SetForce<S>(state, 1, Vec3<S>(S(0), S(0), S(1)), now_ns - 1'000'000);
  EXPECT_EQ(TactileSummaryValidUntil(params, state, now_ns),
            now_ns - 1'000'000 + params.max_sample_age_ns);
  SetForce<S>(state, 2, Vec3<S>(S(0), S(0), S(1)), now_ns + 5);
  EXPECT_EQ(TactileSummaryValidUntil(params, state, now_ns), now_ns);
}

TYPED_TEST(TactileProcessorTest, InvalidChipSettingIsFlaggedWithoutNaN) {
  using S = TypeParam;
  const Airframe airframe;
  TactileProcessorParams<S> params = airframe.Params<S>();
  params.chip_setting = Mlx90393Setting{9, 0};
  params.compensation_enabled = false;
  TactileProcessorState<S> state;

  for (int tick = 0; tick < 20; ++tick) {
    OnTactileSample(params, state, 1, Encode(kFilmT), std::uint8_t(tick), false, tick * kPeriodNs);
  }
  const TactileSummary<S> summary = SummarizeTactile(params, state, 19 * kPeriodNs);

  EXPECT_EQ(state.nodes[0].last_status, DecodeStatus::kNonFiniteInput);
  EXPECT_EQ(state.nodes[0].flagged, 20u);
  EXPECT_FALSE(state.nodes[0].zeroed);
  EXPECT_TRUE(AllFinite(state.nodes[0].force_sensor_n));
  EXPECT_TRUE(AllFinite(summary.external_force_body_n));
  EXPECT_TRUE(std::isfinite(summary.grasp_force_n));
  EXPECT_FALSE(TactileParamsValid(params));
}

TYPED_TEST(TactileProcessorTest, ParamsValidationCatchesDefaultsAndRepeatedIds) {
  using S = TypeParam;
  const Airframe airframe;
  const TactileProcessorParams<S> good = airframe.Params<S>();
  TactileProcessorParams<S> repeated = good;
  repeated.nodes[5].node_id = 1;

  TactileProcessorParams<S> no_average = good;
  no_average.force_average_samples = 0;
  TactileProcessorParams<S> long_average = good;
  long_average.force_average_samples = kMaxForceAverageSamples + 1;

  EXPECT_TRUE(TactileParamsValid(good));
  EXPECT_FALSE(TactileParamsValid(TactileProcessorParams<S>{}));
  EXPECT_FALSE(TactileParamsValid(repeated));
  EXPECT_FALSE(TactileParamsValid(no_average));
  EXPECT_FALSE(TactileParamsValid(long_average));
}

// With an average of 3 a node's force is the mean of the last three forces the same processor
// without one gives, and a flagged sample restarts the mean. The geomagnetic compensation is off so
// that each attitude gives the node another force.
TYPED_TEST(TactileProcessorTest, ForceAverageIsTheMeanOfTheLastSamplesAndRestartsAfterAFlag) {
  using S = TypeParam;
  const Airframe airframe;
  TactileProcessorParams<S> plain = airframe.Params<S>();
  plain.compensation_enabled = false;
  TactileProcessorParams<S> averaged = plain;
  averaged.force_average_samples = 3;
  ASSERT_TRUE(TactileParamsValid(averaged));
  TactileProcessorState<S> plain_state, averaged_state;
  const Mat3<double> level = Mat3<double>::Identity();
  Zero(airframe, plain, plain_state, level);
  Zero(airframe, averaged, averaged_state, level);

  // Node 1's unfiltered force, tick by tick, from the sample that completed the zeroing window
  // (decoded with its own offset, so it is the first in the mean).
  std::vector<Vec3<S>> forces = {plain_state.nodes[0].force_sensor_n};
  int tick = int(plain.zeroing_samples);
  for (int k = 0; k < 6; ++k, ++tick) {
    const Mat3<double> attitude = Rotation(0.3 * (k + 1), {1.0, 0.4 * k, -0.2});
    Tick(airframe, plain, plain_state, attitude, tick);
    Tick(airframe, averaged, averaged_state, attitude, tick);
    forces.push_back(plain_state.nodes[0].force_sensor_n);
    const std::size_t n = std::min<std::size_t>(forces.size(), 3);
    Vec3<S> mean = Vec3<S>::Zero();
    for (std::size_t i = forces.size() - n; i < forces.size(); ++i) mean += forces[i];
    mean /= S(n);
    const S tolerance_n = std::is_same_v<S, float> ? S(1e-5) : S(1e-12);
    EXPECT_LT((averaged_state.nodes[0].force_sensor_n - mean).norm(), tolerance_n) << k;
  }
  // The three-sample mean differs from the last sample: the average did something.
  EXPECT_GT((averaged_state.nodes[0].force_sensor_n - forces.back()).norm(), S(1e-3));

  // A saturated sample keeps the previous force; the next good one starts the mean afresh.
  const Mat3<double> attitude = Rotation(-0.9, {0.3, 1.0, 0.5});
  const std::uint8_t flagged_sequence = std::uint8_t(tick);
  OnReferenceSample(averaged, averaged_state, Encode(airframe.ReferenceField(attitude)),
                    flagged_sequence, false, tick * kPeriodNs);
  const Vec3<S> held = averaged_state.nodes[0].force_sensor_n;
  OnTactileSample(averaged, averaged_state, 1, Encode(airframe.SensorField(0, attitude)),
                  flagged_sequence, true, tick * kPeriodNs);
  EXPECT_EQ(averaged_state.nodes[0].force_sensor_n, held);
  ++tick;
  Tick(airframe, plain, plain_state, attitude, tick);
  Tick(airframe, averaged, averaged_state, attitude, tick);
  const S tolerance_n = std::is_same_v<S, float> ? S(1e-5) : S(1e-12);
  EXPECT_LT((averaged_state.nodes[0].force_sensor_n - plain_state.nodes[0].force_sensor_n).norm(),
            tolerance_n);
}

}  // namespace
}  // namespace hilrig::dut_fw
