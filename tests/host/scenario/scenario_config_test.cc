#include "host/scenario/scenario_config.h"

#include <gtest/gtest.h>

#include <memory>

namespace hilrig::host {
namespace {

ScenarioConfig TickingAt(double physics_rate_hz) {
  proto::Scenario spec;
  spec.set_name("ticks");
  spec.mutable_simulation()->set_duration_s(1);
  spec.mutable_simulation()->set_physics_rate_hz(physics_rate_hz);
  return ResolveScenario(spec, std::nullopt);
}

// The IMU and VIO sample on ticks: their default rates are capped at the tick rate, so the noise
// is scaled for the rate they really sample at (and the report says that rate); a rate the spec
// sets is kept (validation refuses one above the tick rate).
TEST(ResolveSensorsTest, DefaultSensorRatesAreCappedAtTheTickRate) {
  EXPECT_EQ(TickingAt(1000).imu.rate_hz, 1000);
  EXPECT_EQ(TickingAt(2000).imu.rate_hz, 1000);
  EXPECT_EQ(TickingAt(500).imu.rate_hz, 500);
  EXPECT_EQ(TickingAt(500).vio.rate_hz, 30);
  EXPECT_EQ(TickingAt(20).vio.rate_hz, 20);
  proto::Scenario spec;
  spec.set_name("set");
  spec.mutable_simulation()->set_duration_s(1);
  spec.mutable_simulation()->set_physics_rate_hz(500);
  spec.mutable_models()->mutable_imu()->set_rate_hz(250);
  EXPECT_EQ(ResolveScenario(spec, std::nullopt).imu.rate_hz, 250);
}

}  // namespace
}  // namespace hilrig::host
