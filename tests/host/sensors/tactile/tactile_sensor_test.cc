#include "host/sensors/tactile/tactile_sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "host/sensors/earth_field.h"

namespace hilrig::host {
namespace {

// A point dipole at the film centre, moment along the film normal: the cheapest field with the
// right shape (|B| ~ 1 / r^3, Bz > 0 straight above the film), about 3 mT at 10 mm.
class DipoleFilm : public FilmFieldModel {
 public:
  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override {
    constexpr double kMu0Over4Pi = 1e-7;
    const Eigen::Vector3d moment_am2 = pose.orientation * Eigen::Vector3d(0, 0, 0.015);
    const Eigen::Vector3d r = -pose.centre_m;  // film centre to chip
    const double d = r.norm();
    const Eigen::Vector3d u = r / d;
    return kMu0Over4Pi * (3.0 * u * u.dot(moment_am2) - moment_am2) / (d * d * d);
  }
};

TactileSensorParams Ideal() {
  TactileSensorParams params;
  params.chip.noise_enabled = false;
  params.chip.drift_enabled = false;
  params.silicone.damping_enabled = false;
  return params;
}

const Eigen::Vector3d kEarthWorldT(0.0, 2.4e-5, -4.16e-5);

TactileReading SampleOnce(const TactileSensorParams& params, const Eigen::Vector3d& force_n,
                          const Eigen::Quaterniond& attitude) {
  TactileSensorState state = InitialTactileSensorState(params, 7);
  return SampleTactileSensor(params, state, DipoleFilm{}, force_n, attitude, kEarthWorldT, 25.0,
                             1e-3);
}

TEST(TactileSensorTest, NoForceAndNoEarthFieldReadsTheFilmAtRest) {
  TactileSensorParams params = Ideal();
  params.earth_field_enabled = false;
  const TactileReading r =
      SampleOnce(params, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  const Eigen::Vector3d expected = DipoleFilm{}.FieldAtChip(FilmPose{});
  EXPECT_LT((r.field_sensor_t - expected).norm(), 1e-18);
  // Codes are that field quantized at the default gain / RES 0.
  EXPECT_EQ(static_cast<std::int16_t>(r.code[2]), std::lround(expected.z() / 0.242e-6));
  EXPECT_EQ(r.code[0], 0);
  EXPECT_FALSE(r.saturated);
}

TEST(TactileSensorTest, NinetyDegreeYawRotatesTheEarthFieldInTheSensor) {
  TactileSensorParams params = Ideal();
  params.film_present = false;
  const Eigen::Quaterniond yaw_north(
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  const TactileReading level =
      SampleOnce(params, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  const TactileReading yawed = SampleOnce(params, Eigen::Vector3d::Zero(), yaw_north);
  // Level: north (world y) is body y. Nose north: north is body x.
  EXPECT_LT((level.field_sensor_t - kEarthWorldT).norm(), 1e-18);
  EXPECT_LT((yawed.field_sensor_t - Eigen::Vector3d(2.4e-5, 0.0, -4.16e-5)).norm(), 1e-18);
  EXPECT_EQ(static_cast<std::int16_t>(yawed.code[0]), 160);  // 24 uT / 0.150 uT
  EXPECT_EQ(yawed.code[1], 0);
}

TEST(TactileSensorTest, MountingRotatesTheEarthFieldIntoTheSensorFrame) {
  TactileSensorParams params = Ideal();
  params.mounting_body_from_sensor =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX());
  const Eigen::Quaterniond attitude(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const TactileReading r = SampleOnce(params, Eigen::Vector3d::Zero(), attitude);
  const Eigen::Vector3d expected =
      params.mounting_body_from_sensor.conjugate() * (attitude.conjugate() * kEarthWorldT);
  EXPECT_LT((r.earth_field_sensor_t - expected).norm(), 1e-18);
  EXPECT_LT((r.field_sensor_t - r.film_field_t - expected).norm(), 1e-17);
}

TEST(TactileSensorTest, MoreNormalForceBringsTheFilmCloserAndRaisesBz) {
  const TactileSensorParams params = Ideal();
  double previous_bz = 0.0;
  int previous_code = 0;
  for (const double force_n : {0.0, 0.5, 1.0, 2.0, 4.0}) {
    const TactileReading r =
        SampleOnce(params, Eigen::Vector3d(0, 0, force_n), Eigen::Quaterniond::Identity());
    EXPECT_GT(std::abs(r.film_field_t.z()), previous_bz) << force_n;
    EXPECT_GT(static_cast<std::int16_t>(r.code[2]), previous_code) << force_n;
    previous_bz = std::abs(r.film_field_t.z());
    previous_code = static_cast<std::int16_t>(r.code[2]);
  }
}

TEST(TactileSensorTest, ShearMovesTheFilmAndTiltsTheFieldSideways) {
  const TactileSensorParams params = Ideal();
  const TactileReading r =
      SampleOnce(params, Eigen::Vector3d(1.0, 0, 0), Eigen::Quaterniond::Identity());
  EXPECT_GT(r.film_pose.centre_m.x(), 0.0);
  EXPECT_NE(r.film_field_t.x(), 0.0);
  EXPECT_NEAR(r.film_field_t.y(), 0.0, 1e-15);
}

TEST(TactileSensorTest, ReferenceNodeIgnoresForceAndFilm) {
  TactileSensorParams params = Ideal();
  params.film_present = false;
  const TactileReading r =
      SampleOnce(params, Eigen::Vector3d(0, 0, 50.0), Eigen::Quaterniond::Identity());
  EXPECT_EQ(r.film_field_t, Eigen::Vector3d::Zero());
  EXPECT_LT((r.field_sensor_t - kEarthWorldT).norm(), 1e-18);
}

TEST(TactileSensorTest, TheSameSeedAndNodeReproduceTheReadings) {
  TactileSensorParams params;  // noise on
  TactileSensorState a = InitialTactileSensorState(params, 99);
  TactileSensorState b = InitialTactileSensorState(params, 99);
  params.node_id = 2;
  TactileSensorState other_node = InitialTactileSensorState(params, 99);
  const Eigen::Quaterniond level = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d force(0, 0, 1.0);
  const DipoleFilm film;
  bool any_difference = false;
  for (int i = 0; i < 50; ++i) {
    const TactileReading ra =
        SampleTactileSensor(params, a, film, force, level, kEarthWorldT, 25, 0.02);
    const TactileReading rb =
        SampleTactileSensor(params, b, film, force, level, kEarthWorldT, 25, 0.02);
    const TactileReading ro =
        SampleTactileSensor(params, other_node, film, force, level, kEarthWorldT, 25, 0.02);
    EXPECT_EQ(ra.code, rb.code) << i;
    any_difference = any_difference || ra.code != ro.code;
  }
  EXPECT_TRUE(any_difference);
}

// A film field that counts its evaluations, to see the memo skip them.
class CountingFilm : public FilmFieldModel {
 public:
  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override {
    ++calls;
    return DipoleFilm{}.FieldAtChip(pose);
  }
  mutable int calls = 0;
};

TEST(TactileSensorTest, ThePadMemoGivesTheSameReadingsAndSkipsAPadAtRest) {
  const TactileSensorParams params;  // noise, drift and damping on
  const TactileSensorConstants constants = MakeTactileSensorConstants(params, 1e-3);
  TactileSensorState plain = InitialTactileSensorState(params, 5);
  TactileSensorState memoized = plain;
  PadFieldMemo memo;
  const CountingFilm plain_film;
  const CountingFilm memo_film;
  const Eigen::Vector3d earth_body_t =
      EarthFieldInBodyFrame(Eigen::Quaterniond::Identity(), kEarthWorldT);
  // At rest, pressed (the film moving sample after sample), released, at rest again, and -0.0.
  for (int i = 0; i < 400; ++i) {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    if (i >= 100 && i < 200) force = {0.1, 0.0, 2.0};
    if (i >= 350) force.z() = -0.0;
    const TactileReading a = SampleTactileSensor(params, constants, plain, plain_film, force,
                                                 earth_body_t, 30, Eigen::Vector3d::Zero());
    const TactileReading b = SampleTactileSensor(params, constants, memoized, memo_film, force,
                                                 earth_body_t, 30, Eigen::Vector3d::Zero(), &memo);
    ASSERT_EQ(a.code, b.code) << i;
    ASSERT_EQ(a.film_field_t, b.film_field_t) << i;
    ASSERT_EQ(a.film_pose.centre_m, b.film_pose.centre_m) << i;
    ASSERT_EQ(plain.silicone.displacement_m, memoized.silicone.displacement_m) << i;
  }
  EXPECT_EQ(plain_film.calls, 400);
  // The first 100 samples at rest take one evaluation; the film moving after the press and the
  // release (it relaxes towards rest for longer than the run) is evaluated every sample.
  EXPECT_EQ(memo_film.calls, 301);
}

}  // namespace
}  // namespace hilrig::host
