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
