#include "host/fidelity/trace_comparison.h"

#include <gtest/gtest.h>

#include <limits>
#include <optional>

namespace hilrig::host {
namespace {

CapturedTrace Trace(const std::vector<double>& time_s, const std::vector<double>& force_n,
                    const std::vector<double>& load_n, const std::vector<Eigen::Vector3d>& pos_m) {
  CapturedTrace trace;
  trace.time_s = time_s;
  trace.grasp_force_n = force_n;
  trace.load_n = load_n;
  trace.position_m = pos_m;
  return trace;
}

const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

TEST(CompareTracesTest, RmsAndMaxOfTheSampleDifferences) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03, 0.04}, {1, 1, 1, 1}, {2, 2, 2, 2}, {kZero, kZero, kZero, kZero});
  const CapturedTrace run = Trace({0.01, 0.02, 0.03, 0.04}, {1, 2, 1, 3}, {2, 2, 1.5, 2},
                                  {kZero, Eigen::Vector3d(3, 4, 0), kZero, kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_compared, 4u);
  EXPECT_TRUE(errors.complete());
  EXPECT_DOUBLE_EQ(errors.grasp_force_rms_n, std::sqrt((1.0 + 4.0) / 4));
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 2.0);
  EXPECT_DOUBLE_EQ(errors.load_rms_n, std::sqrt(0.25 / 4));
  EXPECT_DOUBLE_EQ(errors.load_max_n, 0.5);
  EXPECT_DOUBLE_EQ(errors.position_rms_m, std::sqrt(25.0 / 4));
  EXPECT_DOUBLE_EQ(errors.position_max_m, 5.0);
}

TEST(CompareTracesTest, ARunThatEndedEarlyCountsTheMissingSamples) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03}, {1, 1, 1}, {0, 0, 0}, {kZero, kZero, kZero});
  const CapturedTrace run = Trace({0.01}, {1.5}, {0}, {kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_compared, 1u);
  EXPECT_EQ(errors.samples_missing, 2u);
  EXPECT_FALSE(errors.complete());
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 0.5);
}

TEST(CompareTracesTest, NonFiniteSamplesAreMissingNotNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CapturedTrace reference = Trace({0.01, 0.02}, {1, 1}, {0, 0}, {kZero, kZero});
  const CapturedTrace run = Trace({0.01, 0.02}, {nan, 1.25}, {0, 0}, {kZero, kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_missing, 1u);
  EXPECT_DOUBLE_EQ(errors.grasp_force_rms_n, 0.25);
}

TEST(CompareTracesTest, EmptyTracesGiveZeroNotNaN) {
  const ErrorMetrics errors = CompareTraces({}, {});

  EXPECT_EQ(errors.samples_compared, 0u);
  EXPECT_FALSE(errors.complete());
  EXPECT_EQ(errors.position_rms_m, 0.0);
}

// As the run goes, a reference sample is read only once a run sample can settle it: the
// comparison holds one reference sample at a time, whatever the length of the run.
TEST(TraceComparisonTest, ReadsTheReferenceOnlyAsFarAsTheRunHasGone) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03, 0.04}, {1, 1, 1, 1}, {0, 0, 0, 0}, {kZero, kZero, kZero, kZero});
  std::size_t read = 0;
  TraceComparison comparison([&]() -> std::optional<ComparedSample> {
    if (read == reference.size()) return std::nullopt;
    return reference.At(read++);
  });

  comparison.AddRun({0.01, kZero, 1.5, 0});
  const std::size_t read_after_first = read;
  comparison.AddRun({0.02, kZero, 1.0, 0});
  const std::size_t read_after_second = read;
  const ErrorMetrics errors = comparison.Finish();

  EXPECT_EQ(read_after_first, 2u);  // the first settled, the second waiting for its run sample
  EXPECT_EQ(read_after_second, 3u);
  EXPECT_EQ(read, 4u);
  EXPECT_EQ(errors.samples_compared, 2u);
  EXPECT_EQ(errors.samples_missing, 2u);  // the run ended at 0.02 s
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 0.5);
}

// A run sample between two reference samples (a run at another trace rate) settles the ones it is
// past as missing and waits for the next: the same pairs as matching the whole traces by time.
TEST(TraceComparisonTest, RunSamplesOffTheReferenceTimesAreMatchedOnlyWithinAMicrosecond) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03}, {1, 2, 3}, {0, 0, 0}, {kZero, kZero, kZero});
  const CapturedTrace run = Trace({0.005, 0.0200005, 0.025, 0.0300000001}, {9, 2.5, 9, 3.25},
                                  {0, 0, 0, 0}, {kZero, kZero, kZero, kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_compared, 2u);
  EXPECT_EQ(errors.samples_missing, 1u);  // 0.01 s: the run has 0.005 s and 0.0200005 s
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 0.5);
}

}  // namespace
}  // namespace hilrig::host
