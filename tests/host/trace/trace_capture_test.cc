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

// One capture feeds the plots as well as the comparison: the estimates, the setpoint and the
// position errors come from the same sample.
TEST(CapturedTraceTest, KeepsThePlottedColumnsOfTheSameSample) {
  TraceSample sample;
  sample.time_s = 0.02;
  sample.position_m = Eigen::Vector3d(3, 4, 1.25);
  sample.reference_m = Eigen::Vector3d(0, 0, 1);
  sample.grasp_force_estimate_n = 0.55;
  sample.grasp_force_setpoint_n = 0.6;
  sample.load_estimate_n = 2.5;
  CapturedTrace trace;

  trace.Add(sample);

  ASSERT_EQ(trace.grasp_force_estimate_n.size(), 1u);
  EXPECT_EQ(trace.grasp_force_estimate_n[0], 0.55);
  EXPECT_EQ(trace.grasp_force_setpoint_n[0], 0.6);
  EXPECT_EQ(trace.load_estimate_n[0], 2.5);
  EXPECT_EQ(trace.altitude_error_m[0], SignalValue(sample, proto::ALTITUDE_ERROR_M));
  EXPECT_EQ(trace.horizontal_error_m[0], 5.0);  // |(3, 4)| from the reference's (0, 0)
  EXPECT_NE(trace.altitude_error_m[0], 0.0);
}

TEST(CapturedTraceTest, AComparedSampleLeavesThePlottedColumnsEmpty) {
  CapturedTrace trace;

  trace.AddCompared(0.01, Eigen::Vector3d(1, 2, 3), 0.5, 1.5);

  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace.position_m[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(trace.grasp_force_n[0], 0.5);
  EXPECT_EQ(trace.load_n[0], 1.5);
  EXPECT_TRUE(trace.altitude_error_m.empty());
  EXPECT_TRUE(trace.grasp_force_estimate_n.empty());
}

}  // namespace
}  // namespace hilrig::host
