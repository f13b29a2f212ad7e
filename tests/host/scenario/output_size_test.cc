// The size of a run's files, estimated before it runs: a day at a 1 kHz trace is worth a warning,
// a minute is not.
#include "host/scenario/output_size.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

ScenarioConfig ConfigOf(const std::string& simulation) {
  const auto spec = ParseScenario("name: \"long\"\nsimulation { " + simulation + " }\n", "x");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), std::nullopt);
}

TEST(OutputSizeTest, ADayAtAKilohertzTraceIsWorthAWarning) {
  const ScenarioConfig day = ConfigOf("duration_s: 86400 trace_rate_hz: 1000");
  // 86.4e6 rows of about 420 bytes, and 4.32e6 reference samples of about 48.
  EXPECT_NEAR(EstimatedOutputBytes(day, false), 86.4e6 * 420 + 86400 * 50 * 48, 1);
  auto warning = OutputSizeWarning(day, false);
  ASSERT_TRUE(warning.has_value());
  EXPECT_THAT(*warning,
              HasSubstr("writes about 36.5 GB (trace.csv 36.3 GB at 1000 Hz over 86400 s"));
  EXPECT_THAT(*warning, Not(HasSubstr("run.mcap")));
  EXPECT_EQ(OutputSizeWarning(ConfigOf("duration_s: 60")), std::nullopt);
}

// The log: 86.4e6 physics and control ticks (IMU 80 bytes; setpoint, step and command 150), as
// many trace samples (270, no envelope) and the reference node's frames (20).
TEST(OutputSizeTest, TheRunsLogCountsEveryExchangeWithTheDut) {
  const ScenarioConfig day = ConfigOf("duration_s: 86400 trace_rate_hz: 1000");
  const double log_bytes = 86.4e6 * (80 + 150 + 270) + 86400 * 50 * 20;
  EXPECT_NEAR(EstimatedOutputBytes(day) - EstimatedOutputBytes(day, false), log_bytes, 1);
  const auto warning = OutputSizeWarning(day);
  ASSERT_TRUE(warning.has_value());
  EXPECT_THAT(*warning, HasSubstr("run.mcap 43.3 GB"));
  EXPECT_THAT(*warning, HasSubstr("--no-mcap leaves it out"));
  // An hour at the default 100 Hz trace writes about 1.1 GB, the log most of it.
  EXPECT_TRUE(OutputSizeWarning(ConfigOf("duration_s: 3600")).has_value());
  EXPECT_EQ(OutputSizeWarning(ConfigOf("duration_s: 3600"), false), std::nullopt);
}

}  // namespace
}  // namespace hilrig::host
