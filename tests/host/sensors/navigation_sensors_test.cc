// The navigation sensors' measurement models against values known without them: the standard
// atmosphere's published table, distances on a sphere, Earth's field turned by a quarter turn.
#include "host/sensors/navigation_sensors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rig/standard_atmosphere.h"

namespace hilrig::host {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

// Great-circle distance on a sphere of Earth's mean radius: independent of the tangent-plane model
// and within 0.5 % of the ellipsoid's distances.
double SphereDistanceM(const GeodeticPoint& a, const GeodeticPoint& b) {
  const double dlat = (b.latitude_deg - a.latitude_deg) * kDegree;
  const double dlon = (b.longitude_deg - a.longitude_deg) * kDegree;
  const double h = std::pow(std::sin(dlat / 2), 2) + std::cos(a.latitude_deg * kDegree) *
                                                         std::cos(b.latitude_deg * kDegree) *
                                                         std::pow(std::sin(dlon / 2), 2);
  return 2 * 6371000.0 * std::asin(std::sqrt(h));
}

TEST(NavigationSensorsTest, TheStandardAtmosphereMatchesItsTable) {
  EXPECT_NEAR(rig::StandardPressurePa(0), 101325.0, 0.01);
  EXPECT_NEAR(rig::StandardTemperatureC(0), 15.0, 1e-9);
  // The ISA table: 89874.6 Pa and 8.5 °C at 1000 m, 54019.9 Pa and -17.5 °C at 5000 m.
  EXPECT_NEAR(rig::StandardPressurePa(1000), 89874.6, 0.5);
  EXPECT_NEAR(rig::StandardTemperatureC(1000), 8.5, 1e-9);
  EXPECT_NEAR(rig::StandardPressurePa(5000), 54019.9, 2.0);
  for (const double altitude_m : {-400.0, 0.0, 408.0, 3000.0, 8000.0}) {
    EXPECT_NEAR(rig::StandardAltitudeM(rig::StandardPressurePa(altitude_m)), altitude_m, 1e-6);
  }
}

TEST(NavigationSensorsTest, ALocalOffsetIsThatFarFromTheOriginOnEarth) {
  const GeodeticPoint origin = kDefaultGeodeticOrigin;
  const GeodeticPoint north = GeodeticFromLocal(origin, {0, 1000, 0});
  EXPECT_NEAR(SphereDistanceM(origin, north), 1000, 5);
  EXPECT_GT(north.latitude_deg, origin.latitude_deg);
  EXPECT_EQ(north.longitude_deg, origin.longitude_deg);
  const GeodeticPoint east = GeodeticFromLocal(origin, {1000, 0, 0});
  EXPECT_NEAR(SphereDistanceM(origin, east), 1000, 5);
  EXPECT_GT(east.longitude_deg, origin.longitude_deg);
  EXPECT_EQ(east.latitude_deg, origin.latitude_deg);
  EXPECT_EQ(GeodeticFromLocal(origin, {0, 0, 2.5}).altitude_m, origin.altitude_m + 2.5);
}

TEST(NavigationSensorsTest, TheMagnetometerReadsEarthsFieldInTheBodyPlusItsStrayField) {
  MagnetometerParams params;
  params.noise_enabled = false;
  params.stray_field_body_t = {1e-6, 0, 0};
  const Eigen::Vector3d earth_t(0, 24e-6, -41.6e-6);  // north and down
  RandomStream rng = RandomStream::FromSeed(1, StreamId::kMagnetometer);
  // Facing north (a quarter turn left of east): north is ahead, the world's east on the right.
  const Eigen::Quaterniond north(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d reading = SampleMagnetometer(params, north, earth_t, rng);
  EXPECT_NEAR(reading.x(), 24e-6 + 1e-6, 1e-12);
  EXPECT_NEAR(reading.y(), 0, 1e-12);
  EXPECT_NEAR(reading.z(), -41.6e-6, 1e-12);
  EXPECT_EQ(rng, RandomStream::FromSeed(1, StreamId::kMagnetometer)) << "no draw without noise";
}

TEST(NavigationSensorsTest, NoiseHasTheStatedSpread) {
  MagnetometerParams mag;
  BarometerParams baro;
  GnssParams gnss;
  RandomStream rng = RandomStream::FromSeed(3, StreamId::kBarometer);
  constexpr int kSamples = 20000;
  double mag_sum_sq = 0, baro_sum_sq = 0, north_sum_sq = 0, up_sum_sq = 0;
  const GeodeticPoint origin = kDefaultGeodeticOrigin;
  for (int i = 0; i < kSamples; ++i) {
    const Eigen::Vector3d m =
        SampleMagnetometer(mag, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), rng);
    mag_sum_sq += m.x() * m.x();
    const double p = SampleBarometer(baro, 100, rng).pressure_pa - rig::StandardPressurePa(100);
    baro_sum_sq += p * p;
    const GnssReading fix =
        SampleGnss(gnss, origin, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), rng);
    const double north_m = SphereDistanceM(
        origin, {fix.position.latitude_deg, origin.longitude_deg, origin.altitude_m});
    north_sum_sq += north_m * north_m;
    up_sum_sq += std::pow(fix.position.altitude_m - origin.altitude_m, 2);
  }
  EXPECT_NEAR(std::sqrt(mag_sum_sq / kSamples), mag.noise_t, 0.03 * mag.noise_t);
  EXPECT_NEAR(std::sqrt(baro_sum_sq / kSamples), baro.noise_pa, 0.03 * baro.noise_pa);
  EXPECT_NEAR(std::sqrt(north_sum_sq / kSamples), gnss.horizontal_noise_m,
              0.03 * gnss.horizontal_noise_m);
  EXPECT_NEAR(std::sqrt(up_sum_sq / kSamples), gnss.vertical_noise_m, 0.03 * gnss.vertical_noise_m);
}

TEST(NavigationSensorsTest, WithoutNoiseTheFixIsExactAndSaysSo) {
  GnssParams params;
  params.noise_enabled = false;
  RandomStream rng;
  const GnssReading fix =
      SampleGnss(params, kDefaultGeodeticOrigin, {3, 4, 5}, {0.5, -0.25, 1}, rng);
  const GeodeticPoint expected = GeodeticFromLocal(kDefaultGeodeticOrigin, {3, 4, 5});
  EXPECT_EQ(fix.position.latitude_deg, expected.latitude_deg);
  EXPECT_EQ(fix.position.longitude_deg, expected.longitude_deg);
  EXPECT_EQ(fix.position.altitude_m, expected.altitude_m);
  EXPECT_EQ(fix.velocity_m_s, Eigen::Vector3d(0.5, -0.25, 1));
  EXPECT_EQ(fix.horizontal_accuracy_m, 0.01);
  BarometerParams baro;
  baro.noise_enabled = false;
  EXPECT_EQ(SampleBarometer(baro, 408, rng).pressure_pa, rig::StandardPressurePa(408));
}

}  // namespace
}  // namespace hilrig::host
