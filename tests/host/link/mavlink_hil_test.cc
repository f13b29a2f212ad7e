// The HIL messages as MAVLink carries them: the frame changes checked on vectors whose answer is
// known by hand (north is the rig's y, down its -z; at rest the accelerometer reads -g along FRD's
// z), and every message taken there and back.
#include "host/link/mavlink_hil.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rig/standard_atmosphere.h"

namespace hilrig::host {
namespace {

void ExpectNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tolerance) {
  EXPECT_LE((actual - expected).norm(), tolerance)
      << actual.transpose() << " vs " << expected.transpose();
}

TEST(MavlinkHilTest, NorthIsTheRigsYAndDownItsMinusZ) {
  ExpectNear(NedFromEnu({1, 2, 3}), {2, 1, -3}, 0);
  ExpectNear(NedFromEnu(NedFromEnu({1, 2, 3})), {1, 2, 3}, 0);
  ExpectNear(FrdFromFlu({1, 2, 3}), {1, -2, -3}, 0);
}

TEST(MavlinkHilTest, AtRestTheAccelerometerReadsMinusGAlongFrdZ) {
  ImuMessage imu;
  imu.accel_m_s2 = {0, 0, 9.81};
  imu.gyro_rad_s = {0.1, 0.2, 0.3};
  const mavlink::HilSensor sensor = HilSensorFrom(imu, 4000);
  EXPECT_EQ(sensor.time_usec, 4000u);
  EXPECT_FLOAT_EQ(sensor.zacc_m_s2, -9.81f);
  EXPECT_FLOAT_EQ(sensor.ygyro_rad_s, -0.2f);
  EXPECT_EQ(sensor.fields_updated, kHilSensorAccelGyro);
  const ImuMessage back = ImuFrom(sensor);
  ExpectNear(back.accel_m_s2, imu.accel_m_s2, 1e-6);
  ExpectNear(back.gyro_rad_s, imu.gyro_rad_s, 1e-6);
}

TEST(MavlinkHilTest, TheMagnetometerAndBarometerGoInGaussAndHectopascalsWithTheirBits) {
  ImuMessage imu;
  imu.accel_m_s2 = {0, 0, 9.81};
  const mavlink::HilSensor imu_only = HilSensorFrom(imu, 4000);
  EXPECT_EQ(imu_only.fields_updated, 0x3Fu);
  EXPECT_FALSE(MagnetometerFrom(imu_only));
  EXPECT_FALSE(BarometerFrom(imu_only));

  MagnetometerMessage mag;
  mag.field_body_t = {24e-6, 0, -41.6e-6};  // facing north, level: 0.24 G ahead, 0.416 G down
  BarometerMessage baro;
  baro.pressure_pa = rig::StandardPressurePa(408);  // 96519 Pa
  baro.temperature_c = 12.3;
  const mavlink::HilSensor sensor = HilSensorFrom(imu, 8000, &mag, &baro);
  EXPECT_EQ(sensor.fields_updated, 0x3Fu | 0x1C0u | 0x1A00u);
  EXPECT_FLOAT_EQ(sensor.xmag_gauss, 0.24f);
  EXPECT_FLOAT_EQ(sensor.ymag_gauss, 0.0f);
  EXPECT_FLOAT_EQ(sensor.zmag_gauss, 0.416f) << "down is FRD's +z";
  EXPECT_FLOAT_EQ(sensor.abs_pressure_hpa, static_cast<float>(baro.pressure_pa / 100));
  EXPECT_NEAR(sensor.pressure_alt, 408, 0.01);
  EXPECT_FLOAT_EQ(sensor.temperature_degc, 12.3f);
  const std::optional<MagnetometerMessage> mag_back = MagnetometerFrom(sensor);
  ASSERT_TRUE(mag_back);
  ExpectNear(mag_back->field_body_t, mag.field_body_t, 1e-11);
  const std::optional<BarometerMessage> baro_back = BarometerFrom(sensor);
  ASSERT_TRUE(baro_back);
  EXPECT_NEAR(baro_back->pressure_pa, baro.pressure_pa, 0.01);

  mavlink::HilSensor partial = sensor;
  partial.fields_updated &= ~0x80u;  // the magnetometer's y missing
  EXPECT_FALSE(MagnetometerFrom(partial));
  partial.abs_pressure_hpa = std::nanf("");
  EXPECT_FALSE(BarometerFrom(partial));
}

TEST(MavlinkHilTest, AGnssFixGoesAsHilGpsInItsUnitsAndBack) {
  GnssMessage fix;
  fix.latitude_deg = 47.3769;
  fix.longitude_deg = 8.5417;
  fix.altitude_m = 409.25;
  fix.velocity_m_s = {1.0, 0.0, -0.5};  // east, sinking
  fix.horizontal_accuracy_m = 0.3;
  fix.vertical_accuracy_m = 0.5;
  fix.satellites = 12;
  const mavlink::HilGps gps = HilGpsFrom(fix, kRunEpochUnixUsec + 4000);
  EXPECT_EQ(gps.time_usec, 1'767'225'600'004'000u);
  EXPECT_EQ(gps.lat_deg_e7, 473769000);
  EXPECT_EQ(gps.lon_deg_e7, 85417000);
  EXPECT_EQ(gps.alt_mm, 409250);
  EXPECT_EQ(gps.eph, 30);
  EXPECT_EQ(gps.epv, 50);
  EXPECT_EQ(gps.vn_cm_s, 0);
  EXPECT_EQ(gps.ve_cm_s, 100);
  EXPECT_EQ(gps.vd_cm_s, 50);
  EXPECT_EQ(gps.vel_cm_s, 100);
  EXPECT_EQ(gps.cog_cdeg, 9000) << "due east";
  EXPECT_EQ(gps.fix_type, 3);
  EXPECT_EQ(gps.satellites_visible, 12);
  const std::optional<GnssMessage> back = GnssFrom(gps);
  ASSERT_TRUE(back);
  EXPECT_NEAR(back->latitude_deg, fix.latitude_deg, 1e-7);
  EXPECT_NEAR(back->altitude_m, fix.altitude_m, 1e-3);
  ExpectNear(back->velocity_m_s, fix.velocity_m_s, 1e-9);

  GnssMessage still = fix;
  still.velocity_m_s = Eigen::Vector3d::Zero();
  EXPECT_EQ(HilGpsFrom(still, 0).cog_cdeg, 65535) << "no course standing still";
  still.velocity_m_s = {0, 400, 0};  // past int16 cm/s
  EXPECT_EQ(HilGpsFrom(still, 0).vn_cm_s, 32767);
  mavlink::HilGps no_fix = gps;
  no_fix.fix_type = 1;
  EXPECT_FALSE(GnssFrom(no_fix));
}

TEST(MavlinkHilTest, AVehicleFacingEastHasANedYawOfAQuarterTurn) {
  EXPECT_NEAR(NedYawFromWorldYaw(0), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(NedYawFromWorldYaw(std::numbers::pi / 2), 0, 1e-12);  // facing north
  // Level and facing east: FRD's x is east, its z down.
  const Eigen::Quaterniond q = NedFrdFromWorldBody(Eigen::Quaterniond::Identity());
  ExpectNear(q * Eigen::Vector3d::UnitX(), {0, 1, 0}, 1e-12);
  ExpectNear(q * Eigen::Vector3d::UnitZ(), {0, 0, 1}, 1e-12);
}

TEST(MavlinkHilTest, AVioPoseGoesThereAndBack) {
  VioMessage vio;
  vio.capture_time_ns = 12'345'000;
  vio.position_m = {0.5, -1.5, 1.25};
  vio.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const mavlink::Odometry odometry = OdometryFrom(vio);
  EXPECT_EQ(odometry.time_usec, 12'345u);
  EXPECT_FLOAT_EQ(odometry.x_m, -1.5f);
  EXPECT_FLOAT_EQ(odometry.z_m, -1.25f);
  EXPECT_EQ(odometry.frame_id, 1);
  EXPECT_EQ(odometry.child_frame_id, 12);
  EXPECT_EQ(odometry.estimator_type, 3);
  EXPECT_TRUE(std::isnan(odometry.vx_m_s));
  const std::optional<VioMessage> back = VioFrom(odometry);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->capture_time_ns, vio.capture_time_ns);
  ExpectNear(back->position_m, vio.position_m, 1e-6);
  EXPECT_LT(back->orientation.angularDistance(vio.orientation), 1e-6);
}

TEST(MavlinkHilTest, ASetpointGoesThereAndBackKeepingThePreviousGrasp) {
  SetpointMessage setpoint;
  setpoint.position_m = {1, 2, 3};
  setpoint.velocity_m_s = {0.1, 0.2, 0.3};
  setpoint.acceleration_m_s2 = {-1, 0, 1};
  setpoint.yaw_rad = 0.4;
  setpoint.grasp_regulate = true;
  const mavlink::SetPositionTargetLocalNed target = PositionTargetFrom(setpoint, 500);
  EXPECT_EQ(target.time_boot_ms, 500u);
  EXPECT_FLOAT_EQ(target.z_m, -3.0f);
  EXPECT_EQ(target.coordinate_frame, 1);
  EXPECT_EQ(target.type_mask, 0x800);
  SetpointMessage grasping;
  grasping.grasp_regulate = true;
  grasping.grasp_force_n = 4;
  const std::optional<SetpointMessage> back = SetpointFrom(target, grasping);
  ASSERT_TRUE(back);
  ExpectNear(back->position_m, setpoint.position_m, 1e-6);
  ExpectNear(back->velocity_m_s, setpoint.velocity_m_s, 1e-6);
  ExpectNear(back->acceleration_m_s2, setpoint.acceleration_m_s2, 1e-6);
  EXPECT_NEAR(back->yaw_rad, 0.4, 1e-6);
  // The grasp is the gripper command's, not the position target's.
  EXPECT_TRUE(back->grasp_regulate);
  EXPECT_EQ(back->grasp_force_n, 4);
  EXPECT_FALSE(SetpointFrom(target, {})->grasp_regulate);
}

TEST(MavlinkHilTest, AGraspGoesThereAndBackAsTheGripperCommand) {
  SetpointMessage setpoint;
  setpoint.position_m = {1, 2, 3};
  setpoint.grasp_regulate = true;
  setpoint.grasp_force_n = 4.0;
  setpoint.grasp_reference_angle_rad = 0.75;
  const mavlink::CommandLong grab = GripperCommandFrom(setpoint);
  EXPECT_EQ(grab.command, 211);
  EXPECT_EQ(grab.param1, 1.0f);
  EXPECT_EQ(grab.param2, 1.0f);  // GRIPPER_ACTION_GRAB
  EXPECT_EQ(grab.param3, 4.0f);
  EXPECT_EQ(grab.param4, 0.75f);
  const std::optional<SetpointMessage> grasped = WithGripperCommand(grab, SetpointMessage{});
  ASSERT_TRUE(grasped);
  EXPECT_TRUE(SameGrasp(*grasped, setpoint));
  EXPECT_EQ(grasped->position_m, Eigen::Vector3d::Zero());  // the position is the target's

  SetpointMessage open = setpoint;
  open.grasp_regulate = false;
  const mavlink::CommandLong release = GripperCommandFrom(open);
  EXPECT_EQ(release.param2, 0.0f);  // GRIPPER_ACTION_RELEASE
  const std::optional<SetpointMessage> released = WithGripperCommand(release, *grasped);
  ASSERT_TRUE(released);
  EXPECT_FALSE(released->grasp_regulate);
  EXPECT_EQ(released->grasp_force_n, 0);
  EXPECT_TRUE(SameGrasp(*released, open));
  EXPECT_FALSE(SameGrasp(*released, setpoint));

  mavlink::CommandLong bad = grab;
  bad.param2 = 2;
  EXPECT_FALSE(WithGripperCommand(bad, {}));
  bad = grab;
  bad.param1 = 3;  // another gripper
  EXPECT_FALSE(WithGripperCommand(bad, {}));
  bad = grab;
  bad.param3 = std::nanf("");
  EXPECT_FALSE(WithGripperCommand(bad, {}));
  bad = grab;
  bad.command = 400;
  EXPECT_FALSE(WithGripperCommand(bad, {}));
}

TEST(MavlinkHilTest, ACanFrameGoesThereAndBackWithSocketCanFlags) {
  const std::array<std::uint8_t, 3> payload = {1, 2, 3};
  for (const rig::CanFrame& frame :
       {rig::CanFrame::Classic(0x123, payload), rig::CanFrame::ClassicExtended(0x1ABCDEF, payload),
        rig::CanFrame::Remote(0x55, 4, false)}) {
    const std::optional<mavlink::CanFrame> message = CanFrameMessageFrom(frame);
    ASSERT_TRUE(message);
    EXPECT_EQ(message->id & 0x1FFFFFFF, frame.id);
    EXPECT_EQ((message->id >> 31) != 0, frame.extended);
    EXPECT_EQ(((message->id >> 30) & 1) != 0, frame.remote);
    EXPECT_EQ(message->len, frame.length);
    EXPECT_EQ(CanFrameFrom(*message), frame);
  }
  EXPECT_FALSE(CanFrameMessageFrom(rig::CanFrame::Fd(0x10, payload, false)));
  EXPECT_FALSE(CanFrameMessageFrom(rig::CanFrame::ErrorFrame(0x4, {})));

  mavlink::CanFrame message;
  message.id = 0x800;  // past 11 bits without the extended flag
  EXPECT_FALSE(CanFrameFrom(message));
  message.id = 0x10;
  message.len = 9;
  EXPECT_FALSE(CanFrameFrom(message));
  message.len = 8;
  message.id = 0x10 | (1u << 29);  // an error frame
  EXPECT_FALSE(CanFrameFrom(message));
}

TEST(MavlinkHilTest, TheDutsEstimatesGoThereAndBackInNed) {
  ActuatorMessage command;
  command.estimated_position_m = {1, 2, 3};
  command.external_force_world_n = {0.1, 0.2, -0.6};
  command.grasp_force_estimate_n = 3.5;
  command.tactile_ready = true;
  for (std::size_t pad = 0; pad < 6; ++pad) {
    command.tactile_force_sensor_n[pad] = Eigen::Vector3d(pad, -0.5 * pad, 0.25);
  }
  const mavlink::DebugFloatArray array = TelemetryFrom(command, 8000);
  EXPECT_TRUE(IsTelemetry(array));
  EXPECT_EQ(array.time_usec, 8000u);
  EXPECT_EQ(std::string(array.name.data(), 6), "hilrig");
  EXPECT_EQ(array.data[0], 2.0f);  // north is the rig's y
  EXPECT_EQ(array.data[5], 0.6f);  // down is the rig's -z
  EXPECT_EQ(array.data[6], 3.5f);
  EXPECT_EQ(array.data[7], 1.0f);
  ActuatorMessage back;
  ApplyTelemetry(array, back);
  ExpectNear(back.estimated_position_m, command.estimated_position_m, 1e-6);
  ExpectNear(back.external_force_world_n, command.external_force_world_n, 1e-6);
  EXPECT_FLOAT_EQ(back.grasp_force_estimate_n, 3.5);
  EXPECT_TRUE(back.tactile_ready);
  for (std::size_t pad = 0; pad < 6; ++pad) {
    ExpectNear(back.tactile_force_sensor_n[pad], command.tactile_force_sensor_n[pad], 1e-6);
  }
  mavlink::DebugFloatArray other = array;
  other.array_id = 2;
  EXPECT_FALSE(IsTelemetry(other));
  other = array;
  other.name[0] = 'H';
  EXPECT_FALSE(IsTelemetry(other));
}

TEST(MavlinkHilTest, OutputsAreZeroUntilArmedAndScaleToTheRotorsMaximum) {
  const ActuatorScale scale{4.0, 0.0, 1.6};
  ActuatorMessage command;
  command.rotor_thrust_n = {1.0, 2.0, 3.0, 5.0};
  command.servo_angle_rad = 0.4;
  const mavlink::HilActuatorControls disarmed = ControlsFrom(command, scale, 8000);
  EXPECT_EQ(disarmed.mode, 1);
  EXPECT_EQ(disarmed.flags, 1u);
  for (int motor = 0; motor < 4; ++motor) EXPECT_EQ(disarmed.controls[motor], 0.0f);
  EXPECT_FLOAT_EQ(disarmed.controls[4], -0.5f);  // the servo moves while the motors may not
  command.armed = true;
  const mavlink::HilActuatorControls armed = ControlsFrom(command, scale, 8000);
  EXPECT_EQ(armed.mode, 129);
  EXPECT_FLOAT_EQ(armed.controls[0], 0.25f);
  EXPECT_FLOAT_EQ(armed.controls[3], 1.0f);  // past the maximum: clamped
  EXPECT_FLOAT_EQ(armed.controls[4], -0.5f);
  const ActuatorMessage back = ActuatorFrom(armed, scale);
  EXPECT_TRUE(back.armed);
  EXPECT_NEAR(back.rotor_thrust_n[1], 2.0, 1e-6);
  EXPECT_NEAR(back.rotor_thrust_n[3], 4.0, 1e-6);
  EXPECT_NEAR(back.servo_angle_rad, 0.4, 1e-6);
}

TEST(MavlinkHilTest, AnAttitudeIsTheSameInEitherEulerConvention) {
  EXPECT_NEAR(NedYawFromWorldYaw(-3.0), std::numbers::pi / 2 + 3.0 - 2 * std::numbers::pi, 1e-12);
  // An attitude from its Euler angles in each convention: the rig's yaw ψ from east, pitch θ nose
  // down and roll φ are PX4's heading π/2 - ψ, pitch -θ (nose up) and roll φ.
  const double yaw = 0.7, pitch = 0.2, roll = -0.3;
  const Eigen::Quaterniond rig = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  const Eigen::Quaterniond ned =
      Eigen::AngleAxisd(std::numbers::pi / 2 - yaw, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  const std::optional<Eigen::Quaterniond> converted =
      WorldBodyFromNedFrd({float(ned.w()), float(ned.x()), float(ned.y()), float(ned.z())});
  ASSERT_TRUE(converted.has_value());
  EXPECT_LT(converted->angularDistance(rig), 1e-6);
  EXPECT_FALSE(WorldBodyFromNedFrd({0, 0, 0, 0}).has_value());
  EXPECT_FALSE(WorldBodyFromNedFrd({NAN, 0, 0, 1}).has_value());
}

TEST(MavlinkHilTest, AnOdometryOfAKnownNedPoseGivesTheEnuVioPose) {
  mavlink::Odometry odometry;  // one metre up, heading east
  odometry.time_usec = 123'456;
  odometry.z_m = -1.0f;
  odometry.q = {static_cast<float>(std::cos(std::numbers::pi / 4)), 0.0f, 0.0f,
                static_cast<float>(std::sin(std::numbers::pi / 4))};
  odometry.frame_id = 1;
  odometry.x_m = 3.0f;   // north
  odometry.y_m = -2.0f;  // east
  const std::optional<VioMessage> vio = VioFrom(odometry);
  ASSERT_TRUE(vio.has_value());
  EXPECT_EQ(vio->capture_time_ns, 123'456'000);
  EXPECT_EQ(vio->position_m, Eigen::Vector3d(-2, 3, 1));
  EXPECT_LT(vio->orientation.angularDistance(Eigen::Quaterniond::Identity()), 1e-6);
  odometry.frame_id = 8;  // MAV_FRAME_BODY_NED: not a pose in the local frame
  EXPECT_FALSE(VioFrom(odometry).has_value());
}

TEST(MavlinkHilTest, ASetPositionTargetGivesTheEnuSetpoint) {
  mavlink::SetPositionTargetLocalNed target;
  target.z_m = -1.0f;
  target.type_mask = 0x800;
  target.coordinate_frame = 1;
  target.x_m = 4.0f;
  target.y_m = 5.0f;
  target.vx_m_s = 0.5f;
  target.vy_m_s = -0.25f;
  target.vz_m_s = 0.125f;
  target.afx_m_s2 = 1.0f;
  target.afy_m_s2 = 2.0f;
  target.afz_m_s2 = -3.0f;
  target.yaw_rad = 0.25f;
  const std::optional<SetpointMessage> setpoint = SetpointFrom(target, {});
  ASSERT_TRUE(setpoint.has_value());
  EXPECT_EQ(setpoint->position_m, Eigen::Vector3d(5, 4, 1));
  EXPECT_EQ(setpoint->velocity_m_s, Eigen::Vector3d(-0.25, 0.5, -0.125));
  EXPECT_EQ(setpoint->acceleration_m_s2, Eigen::Vector3d(2, 1, 3));
  EXPECT_NEAR(setpoint->yaw_rad, std::numbers::pi / 2 - 0.25, 1e-7);
  EXPECT_FALSE(setpoint->grasp_regulate);

  // Ignored dimensions: a position or yaw keeps what it was, a velocity or acceleration is zero.
  SetpointMessage previous;
  previous.position_m = Eigen::Vector3d(7, 8, 9);
  previous.yaw_rad = 1.5;
  target.type_mask = 0x1 | 0x10 | 0x100 | 0x400 | 0x800;  // x (north), vy (east), az, yaw
  const std::optional<SetpointMessage> masked = SetpointFrom(target, previous);
  ASSERT_TRUE(masked.has_value());
  EXPECT_EQ(masked->position_m, Eigen::Vector3d(5, 8, 1));
  EXPECT_EQ(masked->velocity_m_s, Eigen::Vector3d(0, 0.5, -0.125));
  EXPECT_EQ(masked->acceleration_m_s2, Eigen::Vector3d(2, 1, 0));
  EXPECT_EQ(masked->yaw_rad, 1.5);

  target.coordinate_frame = 8;  // body frame: not what this DUT takes
  EXPECT_FALSE(SetpointFrom(target, {}).has_value());
}

}  // namespace
}  // namespace hilrig::host
