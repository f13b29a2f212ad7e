#include "host/trace/trace_csv.h"

#include <bit>
#include <cstring>

namespace hilrig::host {
namespace {

// The row in header order.
std::array<double, TraceCsvWriter::kColumnCount> Columns(const TraceSample& sample) {
  const TraceSample& s = sample;
  std::array<double, TraceCsvWriter::kColumnCount> row = {s.time_s,
                                                          s.position_m.x(),
                                                          s.position_m.y(),
                                                          s.position_m.z(),
                                                          s.reference_m.x(),
                                                          s.reference_m.y(),
                                                          s.reference_m.z(),
                                                          s.velocity_m_s.x(),
                                                          s.velocity_m_s.y(),
                                                          s.velocity_m_s.z(),
                                                          s.roll_pitch_yaw_deg.x(),
                                                          s.roll_pitch_yaw_deg.y(),
                                                          s.roll_pitch_yaw_deg.z(),
                                                          s.tilt_deg,
                                                          SignalValue(s, proto::POSITION_ERROR_M),
                                                          SignalValue(s, proto::HORIZONTAL_ERROR_M),
                                                          SignalValue(s, proto::ALTITUDE_ERROR_M),
                                                          s.rotor_thrust_n[0],
                                                          s.rotor_thrust_n[1],
                                                          s.rotor_thrust_n[2],
                                                          s.rotor_thrust_n[3],
                                                          s.estimated_position_m.x(),
                                                          s.estimated_position_m.y(),
                                                          s.estimated_position_m.z(),
                                                          s.tactile_force_max_n,
                                                          s.tactile_force_error_max_n,
                                                          s.grasp_force_n,
                                                          s.grasp_force_estimate_n,
                                                          s.grasp_force_setpoint_n,
                                                          s.load_n,
                                                          s.load_estimate_n,
                                                          s.object_mass_kg,
                                                          s.servo_angle_rad,
                                                          s.servo_command_rad,
                                                          s.object_damaged ? 1.0 : 0.0,
                                                          s.object_dropped ? 1.0 : 0.0,
                                                          s.ground_force_n,
                                                          s.object_held ? 1.0 : 0.0,
                                                          s.slip_speed_m_s};
  std::size_t next = TraceCsvWriter::kScalarColumnCount;
  for (double force_n : s.pad_force_n) row[next++] = force_n;
  for (double force_n : s.pad_force_estimate_n) row[next++] = force_n;
  return row;
}

}  // namespace

TraceCsvWriter::TraceCsvWriter(std::ostream& out) : out_(out) {
  out_ << "time_s,x_m,y_m,z_m,ref_x_m,ref_y_m,ref_z_m,vx_m_s,vy_m_s,vz_m_s,roll_deg,pitch_deg,"
          "yaw_deg,tilt_deg,position_error_m,horizontal_error_m,altitude_error_m,thrust0_n,"
          "thrust1_n,thrust2_n,thrust3_n,est_x_m,est_y_m,est_z_m,tactile_force_max_n,"
          "tactile_force_error_max_n,grasp_force_n,grasp_force_estimate_n,grasp_force_setpoint_n,"
          "load_n,load_estimate_n,object_mass_kg,servo_angle_rad,servo_command_rad,"
          "object_damaged,object_dropped,ground_force_n,object_held,slip_speed_m_s,"
          "pad0_force_n,pad1_force_n,pad2_force_n,pad3_force_n,pad4_force_n,pad5_force_n,"
          "pad0_force_estimate_n,pad1_force_estimate_n,pad2_force_estimate_n,"
          "pad3_force_estimate_n,pad4_force_estimate_n,pad5_force_estimate_n\n";
}

char* TraceCsvWriter::AppendColumn(double value, ColumnText& previous, char* out) {
  const auto bits = std::bit_cast<std::uint64_t>(value);
  if (previous.length == 0 || previous.bits != bits) {
    const char* end = WriteSignificantDecimal(value, previous.text.data());
    previous.length = static_cast<std::uint8_t>(end - previous.text.data());
    previous.bits = bits;
  }
  // The whole buffer, a fixed-size copy; the bytes past the text are overwritten next.
  std::memcpy(out, previous.text.data(), previous.text.size());
  out += previous.length;
  *out++ = ',';
  return out;
}

void TraceCsvWriter::Write(const TraceSample& sample) {
  const std::array<double, kColumnCount> columns = Columns(sample);
  char* end = line_.data();
  for (std::size_t i = 0; i < kColumnCount; ++i) end = AppendColumn(columns[i], previous_[i], end);
  end[-1] = '\n';  // the last separator
  out_.write(line_.data(), end - line_.data());
}

}  // namespace hilrig::host
