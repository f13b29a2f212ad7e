#include "host/checks/envelope_check.h"

#include <gtest/gtest.h>

#include <limits>

namespace hilrig::host {
namespace {

EnvelopeSpec AltitudeEnvelope(double lower, double upper) {
  EnvelopeSpec envelope;
  envelope.name = "altitude";
  envelope.signal = proto::ALTITUDE_M;
  envelope.lower = lower;
  envelope.upper = upper;
  return envelope;
}

TraceSample AtAltitude(double time_s, double z_m) {
  TraceSample sample;
  sample.time_s = time_s;
  sample.position_m = {0, 0, z_m};
  return sample;
}

TEST(EnvelopeCheckTest, PassesWhenEverySampleIsInside) {
  const EnvelopeCheck check(AltitudeEnvelope(0.5, 1.5));
  EnvelopeProgress progress;
  for (double z : {1.0, 1.2, 0.8}) EXPECT_FALSE(check.Observe(AtAltitude(0, z), progress));
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::PASS);
  EXPECT_TRUE(result.meets_expectation());
  EXPECT_EQ(result.samples_checked(), 3u);
  EXPECT_NEAR(result.margin(), 0.3, 1e-12);
}

TEST(EnvelopeCheckTest, RecordsWorstValueTimeAndFirstViolation) {
  const EnvelopeCheck check(AltitudeEnvelope(0.5, 1.5));
  EnvelopeProgress progress;
  check.Observe(AtAltitude(1, 1.0), progress);
  EXPECT_TRUE(check.Observe(AtAltitude(2, 1.6), progress));
  EXPECT_TRUE(check.Observe(AtAltitude(3, 1.9), progress));
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::FAIL);
  EXPECT_DOUBLE_EQ(result.worst_value(), 1.9);
  EXPECT_DOUBLE_EQ(result.worst_at_s(), 3);
  EXPECT_DOUBLE_EQ(result.first_violation_at_s(), 2);
  EXPECT_NEAR(result.margin(), -0.4, 1e-12);
}

TEST(EnvelopeCheckTest, NaNSampleIsAViolation) {
  const EnvelopeCheck check(AltitudeEnvelope(0.5, 1.5));
  EnvelopeProgress progress;
  EXPECT_TRUE(check.Observe(AtAltitude(1, std::numeric_limits<double>::quiet_NaN()), progress));
  EXPECT_EQ(check.Result(progress).verdict(), proto::FAIL);
}

TEST(EnvelopeCheckTest, IgnoresSamplesOutsideItsWindow) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.5, 1.5);
  envelope.from_s = 5;
  envelope.until_s = 10;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  EXPECT_FALSE(check.Observe(AtAltitude(1, 0.0), progress));
  EXPECT_FALSE(check.Observe(AtAltitude(11, 0.0), progress));
  check.Observe(AtAltitude(6, 1.0), progress);
  EXPECT_EQ(check.Result(progress).verdict(), proto::PASS);
  EXPECT_EQ(progress.samples_checked, 1u);
}

TEST(EnvelopeCheckTest, NoSampleInWindowFails) {
  const EnvelopeCheck check(AltitudeEnvelope(0.5, 1.5));
  const EnvelopeProgress progress;
  EXPECT_EQ(check.Result(progress).verdict(), proto::FAIL);
}

TEST(EnvelopeCheckTest, ExpectedFailureIsMetByAViolation) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.5, 1.5);
  envelope.expect = EnvelopeVerdict::kFail;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  check.Observe(AtAltitude(1, 0.0), progress);
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::FAIL);
  EXPECT_TRUE(result.meets_expectation());
}

TEST(EnvelopeCheckTest, OneSidedBoundUsesOnlyThatSide) {
  EnvelopeSpec envelope;
  envelope.name = "speed";
  envelope.signal = proto::SPEED_M_S;
  envelope.upper = 2.0;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  TraceSample sample;
  sample.velocity_m_s = {0, 0, -1.5};
  EXPECT_FALSE(check.Observe(sample, progress));
  sample.velocity_m_s = {0, 3, 0};
  EXPECT_TRUE(check.Observe(sample, progress));
}

// Noise of +-0.3 around 1.0 stays outside [0.9, 1.1] sample by sample, but its mean over a
// window of whole periods is exactly 1.0.
TEST(EnvelopeCheckTest, MeanOverAWindowPassesNoiseThatSamplesFail) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.9, 1.1);
  envelope.mean_over_s = 0.04;
  const EnvelopeCheck mean_check(envelope);
  const EnvelopeCheck sample_check(AltitudeEnvelope(0.9, 1.1));
  EnvelopeProgress mean_progress, sample_progress;
  for (int i = 0; i < 100; ++i) {
    const TraceSample sample = AtAltitude(i * 0.01, i % 2 == 0 ? 1.3 : 0.7);
    mean_check.Observe(sample, mean_progress);
    sample_check.Observe(sample, sample_progress);
  }
  EXPECT_EQ(sample_check.Result(sample_progress).verdict(), proto::FAIL);
  const proto::EnvelopeResult mean = mean_check.Result(mean_progress);
  EXPECT_EQ(mean.verdict(), proto::PASS);
  EXPECT_NEAR(mean.worst_value(), 1.0, 1e-12);
  // The first mean is checked once the window is full, at 0.04 s: 96 checks (0.04 .. 0.99), each
  // over the four latest samples.
  EXPECT_EQ(mean.samples_checked(), 96u);
}

TEST(EnvelopeCheckTest, MeanOverAWindowStillCatchesADrift) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.9, 1.1);
  envelope.mean_over_s = 0.1;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  for (int i = 0; i < 100; ++i) check.Observe(AtAltitude(i * 0.01, 1.0 + i * 0.005), progress);
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::FAIL);
  // The mean over the ten samples i-9..i is 1 + 0.005 (i - 4.5): above 1.1 first at i = 25.
  EXPECT_NEAR(result.first_violation_at_s(), 0.25, 0.011);
}

TEST(EnvelopeCheckTest, NaNInTheMeansWindowIsAViolation) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.9, 1.1);
  envelope.mean_over_s = 0.05;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  for (int i = 0; i < 20; ++i) {
    const double z = i == 10 ? std::numeric_limits<double>::quiet_NaN() : 1.0;
    check.Observe(AtAltitude(i * 0.01, z), progress);
  }
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::FAIL);
  EXPECT_NEAR(result.first_violation_at_s(), 0.10, 1e-9);
}

// A thousand samples through a ten-sample window: the window's storage is compacted many times
// on the way, and the last mean is still that of the last ten values, 990 .. 999.
TEST(EnvelopeCheckTest, MeanOverALongRunIsThatOfTheLatestWindow) {
  EnvelopeSpec envelope = AltitudeEnvelope(-2000, 2000);
  envelope.mean_over_s = 0.1;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  for (int i = 0; i < 1000; ++i) check.Observe(AtAltitude(i * 0.01, i), progress);
  const proto::EnvelopeResult result = check.Result(progress);
  EXPECT_EQ(result.verdict(), proto::PASS);
  EXPECT_EQ(result.worst_value(), 994.5);     // closest to the upper bound: the last mean
  EXPECT_EQ(result.samples_checked(), 990u);  // from i = 10, when the window is full
}

// A window shorter than the half-microsecond slack holds no sample at all: its mean is NaN, a
// violation, and nothing reads outside the window.
TEST(EnvelopeCheckTest, AWindowShorterThanTheSlackIsAViolation) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.5, 1.5);
  envelope.mean_over_s = 1e-7;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress progress;
  EXPECT_TRUE(check.Observe(AtAltitude(0.01, 1.0), progress));
  EXPECT_EQ(check.Result(progress).verdict(), proto::FAIL);
}

TEST(EnvelopeCheckTest, ReadGivesWhatObserveFoldsIn) {
  EnvelopeSpec envelope = AltitudeEnvelope(0.5, 1.5);
  envelope.from_s = 1;
  const EnvelopeCheck check(envelope);
  EnvelopeProgress read_progress, observe_progress;
  const EnvelopeReading before = check.Read(AtAltitude(0.5, 2.0), read_progress);
  EXPECT_FALSE(before.checked);
  EXPECT_FALSE(before.violation());
  EXPECT_FALSE(check.Observe(AtAltitude(0.5, 2.0), observe_progress));
  const EnvelopeReading outside = check.Read(AtAltitude(1, 1.6), read_progress);
  EXPECT_TRUE(outside.checked);
  EXPECT_EQ(outside.value, 1.6);
  EXPECT_NEAR(outside.margin, -0.1, 1e-12);
  EXPECT_TRUE(outside.violation());
  EXPECT_TRUE(check.Observe(AtAltitude(1, 1.6), observe_progress));
  EXPECT_NEAR(check.Result(observe_progress).margin(), outside.margin, 1e-12);
}

}  // namespace
}  // namespace hilrig::host
