// The size of a run's files, estimated before it runs: a day at a 1 kHz trace is worth a warning,
// a minute is not.
#include "host/scenario/output_size.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

ScenarioConfig ConfigOf(const std::string& simulation) {
  const auto spec = ParseScenario("name: \"long\"\nsimulation { " + simulation + " }\n", "x");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), std::nullopt);
}

TEST(OutputSizeTest, ADayAtAKilohertzTraceIsWorthAWarning) {
  const ScenarioConfig day = ConfigOf("duration_s: 86400 trace_rate_hz: 1000");
  // 86.4e6 rows of about 420 bytes, and 4.32e6 reference samples of about 48.
  EXPECT_NEAR(EstimatedOutputBytes(day), 86.4e6 * 420 + 86400 * 50 * 48, 1);
  const auto warning = OutputSizeWarning(day);
  ASSERT_TRUE(warning.has_value());
  EXPECT_THAT(*warning,
              HasSubstr("writes about 36.5 GB (trace.csv 36.3 GB at 1000 Hz over 86400 s"));
  EXPECT_EQ(OutputSizeWarning(ConfigOf("duration_s: 60")), std::nullopt);
}

}  // namespace
}  // namespace hilrig::host
