#include "host/fidelity/trace_capture.h"

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

}  // namespace
}  // namespace hilrig::host
