#include "host/link/dut_config_codec.h"

#include <gtest/gtest.h>

#include <bit>
#include <limits>

namespace hilrig::host {
namespace {

constexpr double kThird = 1.0 / 3.0;

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

DutFirmware DistinctFirmware() {
  DutFirmware firmware;
  firmware.flight = dut_fw::DefaultFlightControllerParams<double>(1.234567890123);
  firmware.flight.attitude.inertia_kg_m2 = {kThird, 2 * kThird, 0.1};
  firmware.flight.estimator.max_accel_bias_m_s2 = kThird;
  firmware.flight.load_feedforward = false;
  dut_fw::TactileProcessorParams<double> tactile;
  for (int i = 0; i < 6; ++i) {
    tactile.nodes[i].node_id = static_cast<std::uint8_t>(i + 1);
    tactile.nodes[i].rotation_body_from_sensor(0, 1) = i * kThird;
    tactile.nodes[i].gain_a = {i + kThird, -kThird, 1e-9};
  }
  tactile.film = {2.27851, 0.0010535, 0.878725, -0.0000785667};
  tactile.chip_setting = {5, 2};
  tactile.zeroing_samples = 17;
  tactile.force_average_samples = 5;
  tactile.compensation_enabled = false;
  tactile.max_sample_age_ns = 123'456'789;
  firmware.tactile = tactile;
  firmware.grasp.damping = kThird;
  firmware.grasp.force_feedback = false;
  firmware.external_force_in_position_loop = false;
  return firmware;
}

TEST(DutConfigCodecTest, RoundTripsEveryFieldBitExact) {
  const DutFirmware sent = DistinctFirmware();
  // Through the wire form, bytes and all.
  proto::DutConfig wire;
  ASSERT_TRUE(wire.ParseFromString(ToDutConfig(sent, 1e-3).SerializeAsString()));
  const DutSetup received = FromDutConfig(wire).value();
  EXPECT_EQ(received.control_period_s, 1e-3);
  const auto& f = received.firmware.flight;
  EXPECT_EQ(Bits(f.position.mass_kg), Bits(1.234567890123));
  EXPECT_EQ(f.position.kp_per_s2, sent.flight.position.kp_per_s2);
  EXPECT_EQ(f.admittance.damping_n_s_per_m, sent.flight.admittance.damping_n_s_per_m);
  EXPECT_EQ(f.attitude.k_d_nm_s2, sent.flight.attitude.k_d_nm_s2);
  EXPECT_EQ(Bits(f.attitude.inertia_kg_m2.y()), Bits(2 * kThird));
  EXPECT_EQ(Bits(f.estimator.max_accel_bias_m_s2), Bits(kThird));
  EXPECT_EQ(f.mixer.max_thrust_per_rotor_n, sent.flight.mixer.max_thrust_per_rotor_n);
  EXPECT_FALSE(f.load_feedforward);
  ASSERT_TRUE(received.firmware.tactile.has_value());
  const auto& t = *received.firmware.tactile;
  EXPECT_EQ(t.nodes[5].node_id, 6);
  EXPECT_EQ(Bits(t.nodes[4].rotation_body_from_sensor(0, 1)), Bits(4 * kThird));
  EXPECT_EQ(t.nodes[3].gain_a, sent.tactile->nodes[3].gain_a);
  EXPECT_EQ(Bits(t.film.c2), Bits(-0.0000785667));
  EXPECT_EQ(t.chip_setting.gain_sel, 5);
  EXPECT_EQ(t.chip_setting.resolution, 2);
  EXPECT_EQ(t.zeroing_samples, 17u);
  EXPECT_EQ(t.force_average_samples, 5u);
  EXPECT_FALSE(t.compensation_enabled);
  EXPECT_EQ(t.max_sample_age_ns, 123'456'789);
  EXPECT_EQ(Bits(received.firmware.grasp.damping), Bits(kThird));
  EXPECT_FALSE(received.firmware.grasp.force_feedback);
  EXPECT_FALSE(received.firmware.external_force_in_position_loop);
}

TEST(DutConfigCodecTest, NoTactileStaysNoTactile) {
  DutFirmware sent = DistinctFirmware();
  sent.tactile.reset();
  EXPECT_FALSE(FromDutConfig(ToDutConfig(sent, 1e-3)).value().firmware.tactile.has_value());
}

TEST(DutConfigCodecTest, RefusesANonPositiveOrNonFiniteControlPeriod) {
  for (double period_s : {0.0, -1e-3, std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity()}) {
    const auto setup = FromDutConfig(ToDutConfig(DistinctFirmware(), period_s));
    ASSERT_FALSE(setup.ok()) << period_s;
    EXPECT_NE(setup.error().message.find("control period"), std::string::npos);
  }
}

TEST(DutConfigCodecTest, RefusesTheWrongNumberOfTactileNodes) {
  proto::DutConfig config = ToDutConfig(DistinctFirmware(), 1e-3);
  config.mutable_tactile()->mutable_nodes()->RemoveLast();
  const auto setup = FromDutConfig(config);
  ASSERT_FALSE(setup.ok());
  EXPECT_NE(setup.error().message.find("5 nodes instead of 6"), std::string::npos);
}

TEST(DutConfigCodecTest, RefusesAnInvalidChipSetting) {
  proto::DutConfig config = ToDutConfig(DistinctFirmware(), 1e-3);
  config.mutable_tactile()->set_chip_resolution(4);
  EXPECT_FALSE(FromDutConfig(config).ok());
}

TEST(DutConfigCodecTest, RefusesAMatrixOfTheWrongSize) {
  proto::DutConfig config = ToDutConfig(DistinctFirmware(), 1e-3);
  config.mutable_tactile()->mutable_nodes(2)->mutable_rotation_body_from_sensor()->add_row_major(0);
  const auto setup = FromDutConfig(config);
  ASSERT_FALSE(setup.ok());
  EXPECT_NE(setup.error().message.find("10 values instead of 9"), std::string::npos);
}

struct BadFirmware {
  std::string error;  // the whole message: it names the field and the rule
  void (*edit)(DutFirmware&);
};

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A NaN, a negative, an infinite or an out-of-range number in each part of the firmware.
const BadFirmware kBadFirmware[] = {
    {"flight.position.mass_kg is nan: must be finite and > 0",
     [](DutFirmware& f) { f.flight.position.mass_kg = kNan; }},
    {"flight.admittance.mass_kg.y is -1: must be finite and > 0",
     [](DutFirmware& f) { f.flight.admittance.mass_kg.y() = -1; }},
    {"flight.attitude.k_p_nm_s.z is inf: must be finite and >= 0",
     [](DutFirmware& f) { f.flight.attitude.k_p_nm_s.z() = kInf; }},
    {"flight.attitude.derivative_cutoff_hz is 0: must be finite and > 0",
     [](DutFirmware& f) { f.flight.attitude.derivative_cutoff_hz = 0; }},
    {"flight.position.max_tilt_rad is 2: must lie in [0, 1.5708]",
     [](DutFirmware& f) { f.flight.position.max_tilt_rad = 2; }},
    {"flight.position.max_collective_thrust_n is 1: must be at least min_collective_thrust_n (2)",
     [](DutFirmware& f) {
       f.flight.position.min_collective_thrust_n = 2;
       f.flight.position.max_collective_thrust_n = 1;
     }},
    {"flight.mixer.max_thrust_per_rotor_n is -4: must be finite and > 0",
     [](DutFirmware& f) { f.flight.mixer.max_thrust_per_rotor_n = -4; }},
    {"flight.estimator.position_gain is 1.5: must lie in [0, 1]",
     [](DutFirmware& f) { f.flight.estimator.position_gain = 1.5; }},
    {"flight.estimator.nominal_vio_period_s is nan: must be finite and > 0",
     [](DutFirmware& f) { f.flight.estimator.nominal_vio_period_s = kNan; }},
    {"tactile.nodes[2].node_id is 9: must lie in [1, 6]",
     [](DutFirmware& f) { f.tactile->nodes[2].node_id = 9; }},
    {"tactile.nodes[3].node_id is 1: used by an earlier node",
     [](DutFirmware& f) { f.tactile->nodes[3].node_id = 1; }},
    {"tactile.nodes[4].rotation_body_from_sensor[7] is nan: must be finite",
     [](DutFirmware& f) { f.tactile->nodes[4].rotation_body_from_sensor(2, 1) = kNan; }},
    {"tactile.nodes[5].gain_a.x is -inf: must be finite",
     [](DutFirmware& f) { f.tactile->nodes[5].gain_a.x() = -kInf; }},
    {"tactile.film.k2 is 0: must be finite and not 0",
     [](DutFirmware& f) { f.tactile->film.k2 = 0; }},
    {"tactile.zeroing_samples is 0: must be at least 1",
     [](DutFirmware& f) { f.tactile->zeroing_samples = 0; }},
    {"tactile.force_average_samples is 17: must lie in [1, 16]",
     [](DutFirmware& f) { f.tactile->force_average_samples = 17; }},
    {"tactile.max_sample_age_ns is -5: must be > 0",
     [](DutFirmware& f) { f.tactile->max_sample_age_ns = -5; }},
    {"grasp.mass is nan: must be finite and > 0", [](DutFirmware& f) { f.grasp.mass = kNan; }},
    {"grasp.damping is -65: must be finite and >= 0",
     [](DutFirmware& f) { f.grasp.damping = -65; }},
    {"grasp.closed_angle_rad is -1: must be above open_angle_rad (0)",
     [](DutFirmware& f) { f.grasp.closed_angle_rad = -1; }},
    {"grasp.servo_max_rate_rad_s is 0: must be > 0",
     [](DutFirmware& f) { f.grasp.servo_max_rate_rad_s = 0; }},
};

TEST(DutConfigCodecTest, RefusesNumbersOutOfRangeNamingTheField) {
  for (const BadFirmware& bad : kBadFirmware) {
    DutFirmware firmware = DistinctFirmware();
    bad.edit(firmware);
    const auto setup = FromDutConfig(ToDutConfig(firmware, 1e-3));
    ASSERT_FALSE(setup.ok()) << bad.error;
    EXPECT_EQ(setup.error().message, bad.error);
  }
}

TEST(DutConfigCodecTest, ServoWithoutTravelHoldIsAccepted) {
  DutFirmware firmware = DistinctFirmware();
  firmware.grasp.servo_max_rate_rad_s = kInf;  // the firmware's "no travel hold"
  EXPECT_TRUE(FromDutConfig(ToDutConfig(firmware, 1e-3)).ok());
}

}  // namespace
}  // namespace hilrig::host
