#include "host/trace/trace_capture.h"

#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

TEST(CapturedTraceTest, KeepsTheSamplesColumnsExactly) {
  TraceSample sample;
  sample.time_s = 0.01;
  sample.position_m = Eigen::Vector3d(1.0 / 3, -0.1, 0.5);
  sample.grasp_force_n = 0.6000000000000001;
  sample.load_n = 2.37;
  CapturedTrace trace;

  trace.Add(sample);

  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace.time_s[0], 0.01);
  EXPECT_EQ(trace.position_m[0], Eigen::Vector3d(1.0 / 3, -0.1, 0.5));
  EXPECT_EQ(trace.grasp_force_n[0], 0.6000000000000001);
  EXPECT_EQ(trace.load_n[0], 2.37);
}

// The plotted signals come from the same sample as the compared ones.
TEST(PlottedTraceTest, KeepsThePlottedSignalsOfTheSameSample) {
  TraceSample sample;
  sample.time_s = 0.02;
  sample.position_m = Eigen::Vector3d(3, 4, 1.25);
  sample.reference_m = Eigen::Vector3d(0, 0, 1);
  sample.grasp_force_n = 0.5;
  sample.grasp_force_estimate_n = 0.55;
  sample.grasp_force_setpoint_n = 0.6;
  sample.load_n = 2.4;
  sample.load_estimate_n = 2.5;
  PlottedTrace trace;

  trace.Add(sample);

  const auto only = [](const DecimatedSeries& series) {
    const DecimatedSeries::Points points = series.ToPoints();
    EXPECT_EQ(points.time_s, std::vector<double>{0.02});
    return points.value.size() == 1 ? points.value[0] : -1.0;
  };
  EXPECT_EQ(only(trace.grasp_force_n), 0.5);
  EXPECT_EQ(only(trace.grasp_force_estimate_n), 0.55);
  EXPECT_EQ(only(trace.grasp_force_setpoint_n), 0.6);
  EXPECT_EQ(only(trace.load_n), 2.4);
  EXPECT_EQ(only(trace.load_estimate_n), 2.5);
  EXPECT_EQ(only(trace.altitude_error_m), SignalValue(sample, proto::ALTITUDE_ERROR_M));
  EXPECT_NE(only(trace.altitude_error_m), 0.0);
  EXPECT_EQ(only(trace.horizontal_error_m), 5.0);  // |(3, 4)| from the reference's (0, 0)
}

TEST(PlottedTraceTest, KeepsPositionsReferencesAndEachPadsForces) {
  TraceSample sample;
  sample.time_s = 0.03;
  sample.position_m = Eigen::Vector3d(0.1, 0.2, 0.3);
  sample.reference_m = Eigen::Vector3d(0.4, 0.5, 0.6);
  sample.pad_force_n = {1, 2, 3, 4, 5, 6};
  sample.pad_force_estimate_n = {11, 12, 13, 14, 15, 16};
  PlottedTrace trace;

  trace.Add(sample);

  const auto only = [](const DecimatedSeries& series) {
    const DecimatedSeries::Points points = series.ToPoints();
    return points.value.size() == 1 ? points.value[0] : -1.0;
  };
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(only(trace.position_m[axis]), sample.position_m[axis]);
    EXPECT_EQ(only(trace.reference_m[axis]), sample.reference_m[axis]);
  }
  for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
    EXPECT_EQ(only(trace.pad_force_n[pad]), sample.pad_force_n[pad]);
    EXPECT_EQ(only(trace.pad_force_estimate_n[pad]), sample.pad_force_estimate_n[pad]);
  }
  const auto path = trace.path.ToPoints();
  ASSERT_EQ(path.size(), 1u);
  EXPECT_EQ(path[0].x_m, 0.1);
  EXPECT_EQ(path[0].reference_y_m, 0.5);
}

// A long path keeps at most kMaxPoints + 1 points: every stride-th sample, x and y of the same
// sample, the first and the last one added.
TEST(DecimatedPathTest, ALongPathKeepsEveryStrideThSampleAndTheLast) {
  DecimatedPath path;
  constexpr std::size_t kAdded = 3 * DecimatedPath::kMaxPoints + 7;
  for (std::size_t i = 0; i < kAdded; ++i) {
    const double k = static_cast<double>(i);
    path.Add(Eigen::Vector3d(k, -k, 0), Eigen::Vector3d(2 * k, 3 * k, 0));
  }
  const auto points = path.ToPoints();
  ASSERT_LE(points.size(), DecimatedPath::kMaxPoints + 1);
  EXPECT_GE(points.size(), DecimatedPath::kMaxPoints / 2);
  EXPECT_EQ(path.stride(), 4u);
  EXPECT_EQ(points.front().x_m, 0);
  EXPECT_EQ(points.back().x_m, static_cast<double>(kAdded - 1));
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    EXPECT_EQ(points[i].x_m, static_cast<double>(i * path.stride())) << i;
    EXPECT_EQ(points[i].y_m, -points[i].x_m);
    EXPECT_EQ(points[i].reference_y_m, 3 * points[i].x_m);
  }
}

TEST(DecimatedPathTest, AShortPathComesBackWhole) {
  DecimatedPath path;
  for (int i = 0; i < 10; ++i) path.Add(Eigen::Vector3d(i, 0, 0), Eigen::Vector3d::Zero());
  const auto points = path.ToPoints();
  ASSERT_EQ(points.size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(points[static_cast<std::size_t>(i)].x_m, i);
}

TEST(CapturedTraceTest, AComparedSampleKeepsItsColumns) {
  CapturedTrace trace;

  trace.AddCompared(0.01, Eigen::Vector3d(1, 2, 3), 0.5, 1.5);

  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace.position_m[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(trace.grasp_force_n[0], 0.5);
  EXPECT_EQ(trace.load_n[0], 1.5);
}

}  // namespace
}  // namespace hilrig::host
