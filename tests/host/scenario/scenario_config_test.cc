#include "host/scenario/scenario_config.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

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
  // The full scales: ±16 g and ±2000 °/s unless the spec names its part's.
  EXPECT_NEAR(TickingAt(1000).imu.accel_range_m_s2, 156.9, 0.01);
  EXPECT_NEAR(TickingAt(1000).imu.gyro_range_rad_s, 34.91, 0.01);
  spec.mutable_models()->mutable_imu()->set_accel_range_m_s2(78.5);
  spec.mutable_models()->mutable_imu()->set_gyro_range_rad_s(17.4);
  EXPECT_EQ(ResolveScenario(spec, std::nullopt).imu.accel_range_m_s2, 78.5);
  EXPECT_EQ(ResolveScenario(spec, std::nullopt).imu.gyro_range_rad_s, 17.4);
}

// The navigation sensors: the scene's geodetic origin (Zürich by default), their rates capped at
// the tick rate as the IMU's, their noise with the scene's.
TEST(ResolveSensorsTest, TheNavigationSensorsTakeTheOriginTheTickRateAndTheNoiseSwitch) {
  const ScenarioConfig defaults = TickingAt(1000);
  EXPECT_EQ(defaults.navigation.origin.latitude_deg, 47.3769);
  EXPECT_EQ(defaults.navigation.magnetometer.rate_hz, 100);
  EXPECT_EQ(defaults.navigation.gnss.rate_hz, 10);
  EXPECT_TRUE(defaults.navigation.barometer.noise_enabled);
  EXPECT_EQ(TickingAt(40).navigation.magnetometer.rate_hz, 40);
  EXPECT_EQ(TickingAt(40).navigation.barometer.rate_hz, 40);
  proto::Scenario spec;
  spec.set_name("place");
  spec.mutable_simulation()->set_duration_s(1);
  spec.mutable_models()->set_noise(proto::NOISE_OFF);
  proto::GeodeticOrigin* origin = spec.mutable_environment()->mutable_geodetic_origin();
  origin->set_latitude_deg(-33.9);
  origin->set_longitude_deg(18.4);
  origin->set_altitude_m(10);
  const ScenarioConfig config = ResolveScenario(spec, std::nullopt);
  EXPECT_EQ(config.navigation.origin.latitude_deg, -33.9);
  EXPECT_EQ(config.navigation.origin.longitude_deg, 18.4);
  EXPECT_EQ(config.navigation.origin.altitude_m, 10);
  EXPECT_FALSE(config.navigation.magnetometer.noise_enabled);
  EXPECT_FALSE(config.navigation.gnss.noise_enabled);
}

// Each envelope of the spec resolves into the plain struct the checks read, field by field; a bound
// or window the spec leaves out stays unset (an open side), from_s defaults to the start.
TEST(ResolveEnvelopesTest, EveryFieldOfTheSpecsEnvelopesIsResolved) {
  proto::Scenario spec;
  spec.set_name("envelopes");
  spec.mutable_simulation()->set_duration_s(1);
  proto::Envelope& full = *spec.add_envelopes();
  full.set_name("steady load");
  full.set_signal(proto::LOAD_N);
  full.set_lower(-0.5);
  full.set_upper(2.5);
  full.set_from_s(0.25);
  full.set_until_s(0.75);
  full.set_expect(proto::FAIL);
  full.set_abort_on_violation(true);
  full.set_mean_over_s(0.1);
  proto::Envelope& open = *spec.add_envelopes();
  open.set_name("tilt");
  open.set_signal(proto::TILT_DEG);
  open.set_upper(30);

  const std::vector<EnvelopeSpec> envelopes = ResolveScenario(spec, std::nullopt).envelopes;
  ASSERT_EQ(envelopes.size(), 2u);
  const EnvelopeSpec& resolved = envelopes[0];
  EXPECT_EQ(resolved.name, "steady load");
  EXPECT_EQ(resolved.signal, proto::LOAD_N);
  EXPECT_EQ(resolved.lower, -0.5);
  EXPECT_EQ(resolved.upper, 2.5);
  EXPECT_EQ(resolved.from_s, 0.25);
  EXPECT_EQ(resolved.until_s, 0.75);
  EXPECT_EQ(resolved.expect, EnvelopeVerdict::kFail);
  EXPECT_TRUE(resolved.abort_on_violation);
  EXPECT_EQ(resolved.mean_over_s, 0.1);
  const EnvelopeSpec& defaults = envelopes[1];
  EXPECT_EQ(defaults.name, "tilt");
  EXPECT_EQ(defaults.signal, proto::TILT_DEG);
  EXPECT_FALSE(defaults.lower.has_value());
  EXPECT_EQ(defaults.upper, 30.0);
  EXPECT_EQ(defaults.from_s, 0.0);
  EXPECT_FALSE(defaults.until_s.has_value());
  EXPECT_EQ(defaults.expect, EnvelopeVerdict::kPass);
  EXPECT_FALSE(defaults.abort_on_violation);
  EXPECT_FALSE(defaults.mean_over_s.has_value());
}

}  // namespace
}  // namespace hilrig::host
