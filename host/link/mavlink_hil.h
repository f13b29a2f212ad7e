// The rig's HIL messages as MAVLink carries them to a flight stack and back (docs/mavlink.md): the
// change of frames (the rig's world x east, y north, z up and body x forward, y left, z up;
// MAVLink's NED and FRD), of units, and the actuator map. Both ends of a MAVLink DUT take them from
// here: the rig's link (host/linked_dut/mavlink_dut_link.h) and the PX4 stand-in in dut_emu, so the
// two directions are written side by side and tested as each other's inverse. Nothing here
// allocates; nothing fails (a value out of an output's range is clamped to it).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>

#include "host/link/dut_firmware.h"
#include "host/link/hil_messages.h"
#include "host/mavlink/mavlink_messages.h"
#include "rig/can_frame.h"

namespace hilrig::host {

// (north, east, down) of an (x east, y north, z up) vector, and back: the map is its own inverse.
Eigen::Vector3d NedFromEnu(const Eigen::Vector3d& enu);
// (x, -y, -z): FRD of an FLU body vector, and back.
Eigen::Vector3d FrdFromFlu(const Eigen::Vector3d& flu);
// The rotation FRD to NED of a body whose rotation FLU to the rig's world is `world_body`.
Eigen::Quaterniond NedFrdFromWorldBody(const Eigen::Quaterniond& world_body);
// The rig's FLU-to-world attitude of MAVLink's FRD-to-NED one (w, x, y, z), normalised, w >= 0;
// nullopt when it is not finite or has no length.
std::optional<Eigen::Quaterniond> WorldBodyFromNedFrd(const std::array<float, 4>& q_ned_frd);
// A heading from north, clockwise, of one from east, counter-clockwise, wrapped to [-π, π]; the
// map is its own inverse.
double NedYawFromWorldYaw(double world_yaw_rad);

// The MAVLink time of the rig's time: microseconds, rounded down.
inline std::uint64_t MavlinkTimeUs(std::int64_t time_ns) {
  return time_ns > 0 ? static_cast<std::uint64_t>(time_ns / 1000) : 0;
}

// The exit status of PX4's stand-in (dut_emu --mavlink) when its IMU readings repeated exactly, as
// PX4 marks a sensor stale: the scene needs IMU noise.
inline constexpr int kStandInExitSensorsStale = 4;

// HIL_SENSOR's fields_updated for an accelerometer and a gyro (x, y, z each).
inline constexpr std::uint32_t kHilSensorAccelGyro = 0x3F;

// HIL_SENSOR's fields_updated for the magnetometer (x, y, z) and the barometer (absolute
// pressure, pressure altitude, temperature).
inline constexpr std::uint32_t kHilSensorMag = 0x1C0;
inline constexpr std::uint32_t kHilSensorBaro = 0x1A00;

// The readings of a sensor step as HIL_SENSOR: the IMU (accelerometer and gyro, FRD) always; the
// magnetometer (gauss, FRD) and the barometer (hPa, the standard atmosphere's altitude of that
// pressure, °C) when given, that is when they have a reading newer than the last step's, each
// with its fields_updated bits. Back: each reading whose bits are all set (the stamps left for
// the caller); nullopt for one whose bits are not, or whose values are not finite.
mavlink::HilSensor HilSensorFrom(const ImuMessage& imu, std::uint64_t time_usec,
                                 const MagnetometerMessage* mag = nullptr,
                                 const BarometerMessage* baro = nullptr);
ImuMessage ImuFrom(const mavlink::HilSensor& sensor);
std::optional<MagnetometerMessage> MagnetometerFrom(const mavlink::HilSensor& sensor);
std::optional<BarometerMessage> BarometerFrom(const mavlink::HilSensor& sensor);

// HIL_GPS carries UTC; a lockstep run has no date, so its time 0 is this one
// (2026-01-01T00:00:00Z), the same for every run.
inline constexpr std::uint64_t kRunEpochUnixUsec = 1'767'225'600'000'000;

// A GNSS fix as HIL_GPS at Unix time `time_unix_usec`: a 3D fix, position in degE7 and mm,
// velocities in cm/s (NED, clamped to int16), course over ground from the velocity, and eph / epv
// the fix's accuracy in cm (as PX4 reads them). Back: nullopt for no 3D fix; the stamp is left
// for the caller.
mavlink::HilGps HilGpsFrom(const GnssMessage& fix, std::uint64_t time_unix_usec);
std::optional<GnssMessage> GnssFrom(const mavlink::HilGps& gps);

// A VIO pose as ODOMETRY (estimator VIO, pose in LOCAL_NED, twist FRD and unknown). Back: the
// pose, its capture time time_usec x 1000 ns, the stamp left for the caller; nullopt for a pose
// not in LOCAL_NED, not finite, or at a time past the rig's nanoseconds.
mavlink::Odometry OdometryFrom(const VioMessage& vio);
std::optional<VioMessage> VioFrom(const mavlink::Odometry& odometry);

// A setpoint as SET_POSITION_TARGET_LOCAL_NED (position, velocity, acceleration and yaw; the yaw
// rate ignored), to system 1, component 1. Back: what a dimension the type_mask ignores keeps
// comes from `previous` (position, yaw), or is zero (velocity, acceleration, and an acceleration
// given as a force); nullopt for a frame other than LOCAL_NED or a value that is not finite. The
// grasp is `previous`'s: it travels as MAV_CMD_DO_GRIPPER (GripperCommandFrom). The stamp is left
// for the caller.
mavlink::SetPositionTargetLocalNed PositionTargetFrom(const SetpointMessage& setpoint,
                                                      std::uint32_t time_boot_ms);
std::optional<SetpointMessage> SetpointFrom(const mavlink::SetPositionTargetLocalNed& target,
                                            const SetpointMessage& previous);

// The common set's commands both ends of the link use.
inline constexpr std::uint16_t kMavCmdDoSetMode = 176;
inline constexpr std::uint16_t kMavCmdDoGripper = 211;
inline constexpr std::uint16_t kMavCmdComponentArmDisarm = 400;

// The grasp a setpoint carries as MAV_CMD_DO_GRIPPER to system 1, component 1: gripper 1, grab
// (regulate the grasp force) or release (open). Params 3 and 4, empty in the definition, carry the
// grasp force set-point in N and the servo angle where contact is expected in rad, for a flight
// stack that regulates the force; one that only opens and closes its gripper ignores them.
mavlink::CommandLong GripperCommandFrom(const SetpointMessage& setpoint);
// `setpoint` with the grasp of a MAV_CMD_DO_GRIPPER; nullopt for another command, a gripper other
// than 0 (all) or 1, an action other than release or grab, or a grab whose force or angle is not
// finite.
std::optional<SetpointMessage> WithGripperCommand(const mavlink::CommandLong& command,
                                                  const SetpointMessage& setpoint);
// Whether two setpoints carry the same grasp command.
bool SameGrasp(const SetpointMessage& a, const SetpointMessage& b);

// A CAN frame as CAN_FRAME on bus 0 to system 1, component 1, its id flagged as SocketCAN flags
// it (bit 31: a 29-bit id, bit 30: a remote frame); nullopt for what CAN_FRAME cannot carry (an
// error frame, a CAN FD frame). Back: nullopt for a length over 8, an id out of range for its
// flag, or the error flag (bit 29).
std::optional<mavlink::CanFrame> CanFrameMessageFrom(const rig::CanFrame& frame);
std::optional<rig::CanFrame> CanFrameFrom(const mavlink::CanFrame& message);

// The DUT's estimates for the trace, as the DEBUG_FLOAT_ARRAY named kTelemetryName that a flight
// stack reports on the API link (docs/px4.md gives the layout): its position estimate and
// external force (both NED), its grasp force estimate, whether its pads are zeroed, and the six
// pads' forces in their sensor frames.
inline constexpr std::array<char, 10> kTelemetryName = {'h', 'i', 'l', 'r', 'i', 'g'};
inline constexpr std::uint16_t kTelemetryArrayId = 1;
mavlink::DebugFloatArray TelemetryFrom(const ActuatorMessage& command, std::uint64_t time_usec);
// Whether `array` is the DUT's telemetry (by its name and id).
bool IsTelemetry(const mavlink::DebugFloatArray& array);
// `command` with the estimates of `telemetry` (a value that is not finite passes through, as from
// any other DUT).
void ApplyTelemetry(const mavlink::DebugFloatArray& telemetry, ActuatorMessage& command);

// What HIL_ACTUATOR_CONTROLS's outputs mean for the vehicle the DUT is flashed for: motors 0..3 in
// [0, 1] of each rotor's maximum thrust, in PX4's quad-x order (the rig's rotor order), output 4
// the gripper servo in [-1, 1] over [open, closed].
struct ActuatorScale {
  double max_thrust_per_rotor_n = 0;
  double servo_open_rad = 0;
  double servo_closed_rad = 0;
};
ActuatorScale ActuatorScaleOf(const DutFirmware& firmware);

// The DUT's command as outputs: the motors zero while disarmed, the servo always (a servo angle
// that is not finite reads as open); mode 129 armed or 1, flags 1 (lockstep).
mavlink::HilActuatorControls ControlsFrom(const ActuatorMessage& command,
                                          const ActuatorScale& scale, std::uint64_t time_usec);
// The outputs as the rig's command: thrusts, the servo angle and whether the DUT says it is armed.
ActuatorMessage ActuatorFrom(const mavlink::HilActuatorControls& controls,
                             const ActuatorScale& scale);

}  // namespace hilrig::host
