#include "host/link/mavlink_hil.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "rig/standard_atmosphere.h"

namespace hilrig::host {
namespace {

constexpr std::uint8_t kFrameLocalNed = 1;       // MAV_FRAME_LOCAL_NED
constexpr std::uint8_t kFrameBodyFrd = 12;       // MAV_FRAME_BODY_FRD
constexpr std::uint8_t kEstimatorVio = 3;        // MAV_ESTIMATOR_TYPE_VIO
constexpr std::uint16_t kIgnoreYawRate = 0x800;  // POSITION_TARGET_TYPEMASK_YAW_RATE_IGNORE
constexpr std::uint8_t kModeArmed = 128;         // MAV_MODE_FLAG_SAFETY_ARMED
constexpr std::uint8_t kModeCustom = 1;          // MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
constexpr std::uint64_t kFlagLockstep = 1;       // HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP
constexpr int kServoOutput = 4;
constexpr double kGaussPerTesla = 1e4;
constexpr double kPaPerHpa = 100;
constexpr std::uint8_t kGpsFix3d = 3;  // GPS_FIX_TYPE_3D_FIX
constexpr float kGripperInstance = 1;
constexpr float kGripperRelease = 0;  // GRIPPER_ACTION_RELEASE
constexpr float kGripperGrab = 1;     // GRIPPER_ACTION_GRAB
// CAN_FRAME's id flags, as SocketCAN's can_id.
constexpr std::uint32_t kCanIdExtended = 1u << 31;
constexpr std::uint32_t kCanIdRemote = 1u << 30;
constexpr std::uint32_t kCanIdError = 1u << 29;
// The telemetry array's layout (docs/px4.md): where each estimate begins.
constexpr std::size_t kTelemetryPosition = 0;       // 3: NED, m
constexpr std::size_t kTelemetryExternalForce = 3;  // 3: NED, N
constexpr std::size_t kTelemetryGraspForce = 6;     // N
constexpr std::size_t kTelemetryPadsReady = 7;      // 1: zeroed, 0: not yet
constexpr std::size_t kTelemetryPadForces = 8;      // 6 x 3: each pad's sensor frame, N
// POSITION_TARGET_TYPEMASK: the dimensions a target leaves out.
constexpr std::uint16_t kIgnoreX = 1 << 0;
constexpr std::uint16_t kIgnoreY = 1 << 1;
constexpr std::uint16_t kIgnoreZ = 1 << 2;
constexpr std::uint16_t kIgnoreVx = 1 << 3;
constexpr std::uint16_t kIgnoreVy = 1 << 4;
constexpr std::uint16_t kIgnoreVz = 1 << 5;
constexpr std::uint16_t kIgnoreAx = 1 << 6;
constexpr std::uint16_t kIgnoreAy = 1 << 7;
constexpr std::uint16_t kIgnoreAz = 1 << 8;
constexpr std::uint16_t kForceSet = 1 << 9;  // the acceleration fields carry a force
constexpr std::uint16_t kIgnoreYaw = 1 << 10;
// The latest MAVLink time whose nanoseconds an int64 holds.
constexpr std::uint64_t kMaxTimeUsec = std::numeric_limits<std::int64_t>::max() / 1000;

// NED from the rig's world, as a rotation: n = y, e = x, d = -z.
const Eigen::Matrix3d& NedFromWorld() {
  static const Eigen::Matrix3d matrix =
      (Eigen::Matrix3d() << 0, 1, 0, 1, 0, 0, 0, 0, -1).finished();
  return matrix;
}

// FLU from FRD (and back): half a turn about x.
const Eigen::Matrix3d& FluFromFrd() {
  static const Eigen::Matrix3d matrix = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return matrix;
}

Eigen::Vector3d Vector(float x, float y, float z) { return Eigen::Vector3d(x, y, z); }

}  // namespace

Eigen::Vector3d NedFromEnu(const Eigen::Vector3d& enu) { return NedFromWorld() * enu; }

Eigen::Vector3d FrdFromFlu(const Eigen::Vector3d& flu) { return FluFromFrd() * flu; }

Eigen::Quaterniond NedFrdFromWorldBody(const Eigen::Quaterniond& world_body) {
  return Eigen::Quaterniond(NedFromWorld() * world_body.toRotationMatrix() * FluFromFrd());
}

std::optional<Eigen::Quaterniond> WorldBodyFromNedFrd(const std::array<float, 4>& q_ned_frd) {
  Eigen::Quaterniond q(q_ned_frd[0], q_ned_frd[1], q_ned_frd[2], q_ned_frd[3]);
  if (!q.coeffs().allFinite() || !(q.norm() > 1e-6)) return std::nullopt;
  Eigen::Quaterniond world_body(NedFromWorld().transpose() * q.normalized().toRotationMatrix() *
                                FluFromFrd());
  // q and -q are one attitude; a non-negative w makes the result one number.
  if (world_body.w() < 0) world_body.coeffs() = -world_body.coeffs();
  return world_body;
}

double NedYawFromWorldYaw(double world_yaw_rad) {
  return std::remainder(std::numbers::pi / 2 - world_yaw_rad, 2 * std::numbers::pi);
}

mavlink::HilSensor HilSensorFrom(const ImuMessage& imu, std::uint64_t time_usec,
                                 const MagnetometerMessage* mag, const BarometerMessage* baro) {
  mavlink::HilSensor sensor;
  sensor.time_usec = time_usec;
  const Eigen::Vector3d accel = FrdFromFlu(imu.accel_m_s2);
  const Eigen::Vector3d gyro = FrdFromFlu(imu.gyro_rad_s);
  sensor.xacc_m_s2 = static_cast<float>(accel.x());
  sensor.yacc_m_s2 = static_cast<float>(accel.y());
  sensor.zacc_m_s2 = static_cast<float>(accel.z());
  sensor.xgyro_rad_s = static_cast<float>(gyro.x());
  sensor.ygyro_rad_s = static_cast<float>(gyro.y());
  sensor.zgyro_rad_s = static_cast<float>(gyro.z());
  sensor.fields_updated = kHilSensorAccelGyro;
  if (mag != nullptr) {
    const Eigen::Vector3d field_gauss = FrdFromFlu(mag->field_body_t) * kGaussPerTesla;
    sensor.xmag_gauss = static_cast<float>(field_gauss.x());
    sensor.ymag_gauss = static_cast<float>(field_gauss.y());
    sensor.zmag_gauss = static_cast<float>(field_gauss.z());
    sensor.fields_updated |= kHilSensorMag;
  }
  if (baro != nullptr) {
    sensor.abs_pressure_hpa = static_cast<float>(baro->pressure_pa / kPaPerHpa);
    sensor.pressure_alt = static_cast<float>(rig::StandardAltitudeM(baro->pressure_pa));
    sensor.temperature_degc = static_cast<float>(baro->temperature_c);
    sensor.fields_updated |= kHilSensorBaro;
  }
  return sensor;
}

std::optional<MagnetometerMessage> MagnetometerFrom(const mavlink::HilSensor& sensor) {
  if ((sensor.fields_updated & kHilSensorMag) != kHilSensorMag) return std::nullopt;
  MagnetometerMessage mag;
  mag.field_body_t =
      FrdFromFlu(Vector(sensor.xmag_gauss, sensor.ymag_gauss, sensor.zmag_gauss)) / kGaussPerTesla;
  if (!mag.field_body_t.allFinite()) return std::nullopt;
  return mag;
}

std::optional<BarometerMessage> BarometerFrom(const mavlink::HilSensor& sensor) {
  if ((sensor.fields_updated & kHilSensorBaro) != kHilSensorBaro) return std::nullopt;
  BarometerMessage baro;
  baro.pressure_pa = double{sensor.abs_pressure_hpa} * kPaPerHpa;
  baro.temperature_c = sensor.temperature_degc;
  if (!std::isfinite(baro.pressure_pa) || !std::isfinite(baro.temperature_c)) return std::nullopt;
  return baro;
}

mavlink::HilGps HilGpsFrom(const GnssMessage& fix, std::uint64_t time_unix_usec) {
  const auto scaled = [](double value, double scale, double low, double high) {
    const double v = std::isfinite(value) ? std::round(value * scale) : 0.0;
    return std::clamp(v, low, high);
  };
  constexpr double kInt16Max = std::numeric_limits<std::int16_t>::max();
  constexpr double kUint16Max = std::numeric_limits<std::uint16_t>::max();
  constexpr double kInt32Max = std::numeric_limits<std::int32_t>::max();
  mavlink::HilGps gps;
  gps.time_usec = time_unix_usec;
  gps.lat_deg_e7 = static_cast<std::int32_t>(scaled(fix.latitude_deg, 1e7, -9e8, 9e8));
  gps.lon_deg_e7 = static_cast<std::int32_t>(scaled(fix.longitude_deg, 1e7, -1.8e9, 1.8e9));
  gps.alt_mm = static_cast<std::int32_t>(scaled(fix.altitude_m, 1e3, -kInt32Max, kInt32Max));
  // eph and epv: the fix's accuracy in cm, capped below UINT16_MAX (which says "unknown").
  gps.eph = static_cast<std::uint16_t>(scaled(fix.horizontal_accuracy_m, 100, 1, kUint16Max - 1));
  gps.epv = static_cast<std::uint16_t>(scaled(fix.vertical_accuracy_m, 100, 1, kUint16Max - 1));
  const Eigen::Vector3d velocity_ned = NedFromEnu(fix.velocity_m_s);
  gps.vn_cm_s = static_cast<std::int16_t>(scaled(velocity_ned.x(), 100, -kInt16Max, kInt16Max));
  gps.ve_cm_s = static_cast<std::int16_t>(scaled(velocity_ned.y(), 100, -kInt16Max, kInt16Max));
  gps.vd_cm_s = static_cast<std::int16_t>(scaled(velocity_ned.z(), 100, -kInt16Max, kInt16Max));
  const double ground_speed = std::hypot(velocity_ned.x(), velocity_ned.y());
  gps.vel_cm_s = static_cast<std::uint16_t>(scaled(ground_speed, 100, 0, kUint16Max - 1));
  // Course over ground, degrees from north in [0, 360); UINT16_MAX when standing still.
  double course_deg = std::atan2(velocity_ned.y(), velocity_ned.x()) * 180 / std::numbers::pi;
  if (course_deg < 0) course_deg += 360;
  gps.cog_cdeg = ground_speed > 0 && std::isfinite(course_deg)
                     ? static_cast<std::uint16_t>(std::min(std::round(course_deg * 100), 35999.0))
                     : std::numeric_limits<std::uint16_t>::max();
  gps.fix_type = kGpsFix3d;
  gps.satellites_visible = fix.satellites;
  return gps;
}

std::optional<GnssMessage> GnssFrom(const mavlink::HilGps& gps) {
  if (gps.fix_type < kGpsFix3d) return std::nullopt;
  GnssMessage fix;
  fix.latitude_deg = gps.lat_deg_e7 * 1e-7;
  fix.longitude_deg = gps.lon_deg_e7 * 1e-7;
  fix.altitude_m = gps.alt_mm * 1e-3;
  fix.velocity_m_s = NedFromEnu(Eigen::Vector3d(gps.vn_cm_s, gps.ve_cm_s, gps.vd_cm_s) * 1e-2);
  fix.horizontal_accuracy_m = gps.eph * 1e-2;
  fix.vertical_accuracy_m = gps.epv * 1e-2;
  fix.satellites = gps.satellites_visible;
  return fix;
}

ImuMessage ImuFrom(const mavlink::HilSensor& sensor) {
  ImuMessage imu;
  imu.accel_m_s2 = FrdFromFlu(Vector(sensor.xacc_m_s2, sensor.yacc_m_s2, sensor.zacc_m_s2));
  imu.gyro_rad_s = FrdFromFlu(Vector(sensor.xgyro_rad_s, sensor.ygyro_rad_s, sensor.zgyro_rad_s));
  return imu;
}

mavlink::Odometry OdometryFrom(const VioMessage& vio) {
  constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
  mavlink::Odometry odometry;
  odometry.time_usec = MavlinkTimeUs(vio.capture_time_ns);
  const Eigen::Vector3d position = NedFromEnu(vio.position_m);
  odometry.x_m = static_cast<float>(position.x());
  odometry.y_m = static_cast<float>(position.y());
  odometry.z_m = static_cast<float>(position.z());
  const Eigen::Quaterniond q = NedFrdFromWorldBody(vio.orientation).normalized();
  odometry.q = {static_cast<float>(q.w()), static_cast<float>(q.x()), static_cast<float>(q.y()),
                static_cast<float>(q.z())};
  odometry.vx_m_s = odometry.vy_m_s = odometry.vz_m_s = kUnknown;
  odometry.rollspeed_rad_s = odometry.pitchspeed_rad_s = odometry.yawspeed_rad_s = kUnknown;
  odometry.pose_covariance[0] = kUnknown;
  odometry.velocity_covariance[0] = kUnknown;
  odometry.frame_id = kFrameLocalNed;
  odometry.child_frame_id = kFrameBodyFrd;
  odometry.estimator_type = kEstimatorVio;
  return odometry;
}

std::optional<VioMessage> VioFrom(const mavlink::Odometry& odometry) {
  if (odometry.frame_id != kFrameLocalNed || odometry.time_usec > kMaxTimeUsec) return std::nullopt;
  const Eigen::Vector3d position = NedFromEnu(Vector(odometry.x_m, odometry.y_m, odometry.z_m));
  const std::optional<Eigen::Quaterniond> orientation = WorldBodyFromNedFrd(odometry.q);
  if (!position.allFinite() || !orientation) return std::nullopt;
  VioMessage vio;
  vio.capture_time_ns = static_cast<std::int64_t>(odometry.time_usec) * 1000;
  vio.position_m = position;
  vio.orientation = *orientation;
  return vio;
}

mavlink::SetPositionTargetLocalNed PositionTargetFrom(const SetpointMessage& setpoint,
                                                      std::uint32_t time_boot_ms) {
  mavlink::SetPositionTargetLocalNed target;
  target.time_boot_ms = time_boot_ms;
  const Eigen::Vector3d position = NedFromEnu(setpoint.position_m);
  const Eigen::Vector3d velocity = NedFromEnu(setpoint.velocity_m_s);
  const Eigen::Vector3d acceleration = NedFromEnu(setpoint.acceleration_m_s2);
  target.x_m = static_cast<float>(position.x());
  target.y_m = static_cast<float>(position.y());
  target.z_m = static_cast<float>(position.z());
  target.vx_m_s = static_cast<float>(velocity.x());
  target.vy_m_s = static_cast<float>(velocity.y());
  target.vz_m_s = static_cast<float>(velocity.z());
  target.afx_m_s2 = static_cast<float>(acceleration.x());
  target.afy_m_s2 = static_cast<float>(acceleration.y());
  target.afz_m_s2 = static_cast<float>(acceleration.z());
  target.yaw_rad = static_cast<float>(NedYawFromWorldYaw(setpoint.yaw_rad));
  target.type_mask = kIgnoreYawRate;
  target.target_system = 1;
  target.target_component = 1;
  target.coordinate_frame = kFrameLocalNed;
  return target;
}

std::optional<SetpointMessage> SetpointFrom(const mavlink::SetPositionTargetLocalNed& target,
                                            const SetpointMessage& previous) {
  if (target.coordinate_frame != kFrameLocalNed) return std::nullopt;
  const auto used = [mask = target.type_mask](std::uint16_t ignore_bit) {
    return (mask & ignore_bit) == 0;
  };
  // The world's (x, y, z) are NED's (east, north, -down): each axis with its NED axis's bit.
  const std::array<std::uint16_t, 3> position_bits = {kIgnoreY, kIgnoreX, kIgnoreZ};
  const std::array<std::uint16_t, 3> velocity_bits = {kIgnoreVy, kIgnoreVx, kIgnoreVz};
  const std::array<std::uint16_t, 3> acceleration_bits = {kIgnoreAy, kIgnoreAx, kIgnoreAz};
  const Eigen::Vector3d position = NedFromEnu(Vector(target.x_m, target.y_m, target.z_m));
  const Eigen::Vector3d velocity = NedFromEnu(Vector(target.vx_m_s, target.vy_m_s, target.vz_m_s));
  const Eigen::Vector3d acceleration =
      NedFromEnu(Vector(target.afx_m_s2, target.afy_m_s2, target.afz_m_s2));
  // A force is no acceleration, and the rig's controllers take none: it is left out.
  const bool acceleration_given = used(kForceSet);
  SetpointMessage setpoint = previous;
  for (int axis = 0; axis < 3; ++axis) {
    setpoint.position_m[axis] =
        used(position_bits[axis]) ? position[axis] : previous.position_m[axis];
    setpoint.velocity_m_s[axis] = used(velocity_bits[axis]) ? velocity[axis] : 0.0;
    setpoint.acceleration_m_s2[axis] =
        acceleration_given && used(acceleration_bits[axis]) ? acceleration[axis] : 0.0;
  }
  if (used(kIgnoreYaw)) setpoint.yaw_rad = NedYawFromWorldYaw(target.yaw_rad);
  if (!setpoint.position_m.allFinite() || !setpoint.velocity_m_s.allFinite() ||
      !setpoint.acceleration_m_s2.allFinite() || !std::isfinite(setpoint.yaw_rad)) {
    return std::nullopt;
  }
  return setpoint;
}

mavlink::CommandLong GripperCommandFrom(const SetpointMessage& setpoint) {
  mavlink::CommandLong command;
  command.command = kMavCmdDoGripper;
  command.param1 = kGripperInstance;
  command.param2 = setpoint.grasp_regulate ? kGripperGrab : kGripperRelease;
  command.param3 = setpoint.grasp_regulate ? static_cast<float>(setpoint.grasp_force_n) : 0;
  command.param4 =
      setpoint.grasp_regulate ? static_cast<float>(setpoint.grasp_reference_angle_rad) : 0;
  command.target_system = 1;
  command.target_component = 1;
  return command;
}

std::optional<SetpointMessage> WithGripperCommand(const mavlink::CommandLong& command,
                                                  const SetpointMessage& setpoint) {
  if (command.command != kMavCmdDoGripper) return std::nullopt;
  if (command.param1 != 0 && command.param1 != kGripperInstance) return std::nullopt;
  const bool grab = command.param2 == kGripperGrab;
  if (!grab && command.param2 != kGripperRelease) return std::nullopt;
  if (grab && !(std::isfinite(command.param3) && std::isfinite(command.param4))) {
    return std::nullopt;
  }
  SetpointMessage grasped = setpoint;
  grasped.grasp_regulate = grab;
  grasped.grasp_force_n = grab ? command.param3 : 0;
  grasped.grasp_reference_angle_rad = grab ? command.param4 : 0;
  return grasped;
}

bool SameGrasp(const SetpointMessage& a, const SetpointMessage& b) {
  if (a.grasp_regulate != b.grasp_regulate) return false;
  return !a.grasp_regulate || (a.grasp_force_n == b.grasp_force_n &&
                               a.grasp_reference_angle_rad == b.grasp_reference_angle_rad);
}

std::optional<mavlink::CanFrame> CanFrameMessageFrom(const rig::CanFrame& frame) {
  if (frame.error || frame.fd || frame.length > rig::CanFrame::kMaxClassicPayload) {
    return std::nullopt;
  }
  mavlink::CanFrame message;
  message.id = frame.id | (frame.extended ? kCanIdExtended : 0) | (frame.remote ? kCanIdRemote : 0);
  message.target_system = 1;
  message.target_component = 1;
  message.len = frame.length;
  if (!frame.remote) std::copy_n(frame.data.begin(), frame.length, message.data.begin());
  return message;
}

std::optional<rig::CanFrame> CanFrameFrom(const mavlink::CanFrame& message) {
  if (message.len > rig::CanFrame::kMaxClassicPayload || (message.id & kCanIdError) != 0) {
    return std::nullopt;
  }
  rig::CanFrame frame;
  frame.extended = (message.id & kCanIdExtended) != 0;
  frame.remote = (message.id & kCanIdRemote) != 0;
  frame.id = message.id & rig::kMaxExtendedId;
  frame.length = message.len;
  if (!frame.remote) std::copy_n(message.data.begin(), message.len, frame.data.begin());
  if (!rig::IsValidFrame(frame)) return std::nullopt;
  return frame;
}

mavlink::DebugFloatArray TelemetryFrom(const ActuatorMessage& command, std::uint64_t time_usec) {
  mavlink::DebugFloatArray array;
  array.time_usec = time_usec;
  array.array_id = kTelemetryArrayId;
  array.name = kTelemetryName;
  const auto put = [&array](std::size_t at, const Eigen::Vector3d& vector) {
    for (int axis = 0; axis < 3; ++axis) array.data[at + axis] = static_cast<float>(vector[axis]);
  };
  put(kTelemetryPosition, NedFromEnu(command.estimated_position_m));
  put(kTelemetryExternalForce, NedFromEnu(command.external_force_world_n));
  array.data[kTelemetryGraspForce] = static_cast<float>(command.grasp_force_estimate_n);
  array.data[kTelemetryPadsReady] = command.tactile_ready ? 1.0f : 0.0f;
  for (std::size_t pad = 0; pad < command.tactile_force_sensor_n.size(); ++pad) {
    put(kTelemetryPadForces + 3 * pad, command.tactile_force_sensor_n[pad]);
  }
  return array;
}

bool IsTelemetry(const mavlink::DebugFloatArray& array) {
  return array.array_id == kTelemetryArrayId && array.name == kTelemetryName;
}

void ApplyTelemetry(const mavlink::DebugFloatArray& telemetry, ActuatorMessage& command) {
  const auto get = [&telemetry](std::size_t at) {
    return Eigen::Vector3d(telemetry.data[at], telemetry.data[at + 1], telemetry.data[at + 2]);
  };
  command.estimated_position_m = NedFromEnu(get(kTelemetryPosition));
  command.external_force_world_n = NedFromEnu(get(kTelemetryExternalForce));
  command.grasp_force_estimate_n = telemetry.data[kTelemetryGraspForce];
  command.tactile_ready = telemetry.data[kTelemetryPadsReady] == 1.0f;
  for (std::size_t pad = 0; pad < command.tactile_force_sensor_n.size(); ++pad) {
    command.tactile_force_sensor_n[pad] = get(kTelemetryPadForces + 3 * pad);
  }
}

ActuatorScale ActuatorScaleOf(const DutFirmware& firmware) {
  return {firmware.flight.mixer.max_thrust_per_rotor_n, firmware.grasp.open_angle_rad,
          firmware.grasp.closed_angle_rad};
}

mavlink::HilActuatorControls ControlsFrom(const ActuatorMessage& command,
                                          const ActuatorScale& scale, std::uint64_t time_usec) {
  mavlink::HilActuatorControls controls;
  controls.time_usec = time_usec;
  controls.flags = kFlagLockstep;
  controls.mode = static_cast<std::uint8_t>(kModeCustom | (command.armed ? kModeArmed : 0));
  if (command.armed && scale.max_thrust_per_rotor_n > 0) {
    for (int rotor = 0; rotor < 4; ++rotor) {
      const double fraction = command.rotor_thrust_n[rotor] / scale.max_thrust_per_rotor_n;
      controls.controls[rotor] =
          static_cast<float>(std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0);
    }
  }
  // The gripper servo moves whether or not the motors may: [open, closed] onto [-1, 1].
  const double range = scale.servo_closed_rad - scale.servo_open_rad;
  const double closed = range > 0 ? (command.servo_angle_rad - scale.servo_open_rad) / range : 0;
  controls.controls[kServoOutput] =
      static_cast<float>(2 * (std::isfinite(closed) ? std::clamp(closed, 0.0, 1.0) : 0.0) - 1);
  return controls;
}

ActuatorMessage ActuatorFrom(const mavlink::HilActuatorControls& controls,
                             const ActuatorScale& scale) {
  ActuatorMessage command;
  command.armed = (controls.mode & kModeArmed) != 0;
  for (int rotor = 0; rotor < 4; ++rotor) {
    const double output = std::isfinite(controls.controls[rotor]) ? controls.controls[rotor] : 0;
    command.rotor_thrust_n[rotor] = std::clamp(output, 0.0, 1.0) * scale.max_thrust_per_rotor_n;
  }
  const double servo =
      std::isfinite(controls.controls[kServoOutput]) ? controls.controls[kServoOutput] : -1;
  command.servo_angle_rad =
      scale.servo_open_rad +
      (std::clamp(servo, -1.0, 1.0) + 1) / 2 * (scale.servo_closed_rad - scale.servo_open_rad);
  return command;
}

}  // namespace hilrig::host
