#include "host/trace/trace_csv.h"

#include <bit>
#include <charconv>
#include <cstring>

#include "rig/check.h"

namespace hilrig::host {

TraceCsvWriter::TraceCsvWriter(std::ostream& out) : out_(out) {
  out_ << "time_s,x_m,y_m,z_m,ref_x_m,ref_y_m,ref_z_m,vx_m_s,vy_m_s,vz_m_s,roll_deg,pitch_deg,"
          "yaw_deg,tilt_deg,position_error_m,horizontal_error_m,altitude_error_m,thrust0_n,"
          "thrust1_n,thrust2_n,thrust3_n,est_x_m,est_y_m,est_z_m,tactile_force_max_n,"
          "tactile_force_error_max_n,grasp_force_n,grasp_force_estimate_n,grasp_force_setpoint_n,"
          "load_n,load_estimate_n,object_mass_kg,servo_angle_rad,servo_command_rad,"
          "object_damaged,object_dropped\n";
}

void TraceCsvWriter::Append(double value) {
  HILRIG_CHECK(column_ < kColumnCount, "a trace row has more columns than kColumnCount");
  ColumnText& column = previous_[column_++];
  const auto bits = std::bit_cast<std::uint64_t>(value);
  if (!column.valid || column.bits != bits) {
    const auto result =
        std::to_chars(column.text.data(), column.text.data() + column.text.size(), value);
    column.length = static_cast<std::uint8_t>(result.ptr - column.text.data());
    column.bits = bits;
    column.valid = true;
  }
  std::memcpy(line_.data() + line_length_, column.text.data(), column.length);
  line_length_ += column.length;
  line_[line_length_++] = ',';
}

void TraceCsvWriter::Write(const TraceSample& sample) {
  column_ = 0;
  line_length_ = 0;
  Append(sample.time_s);
  for (int i = 0; i < 3; ++i) Append(sample.position_m(i));
  for (int i = 0; i < 3; ++i) Append(sample.reference_m(i));
  for (int i = 0; i < 3; ++i) Append(sample.velocity_m_s(i));
  for (int i = 0; i < 3; ++i) Append(sample.roll_pitch_yaw_deg(i));
  Append(sample.tilt_deg);
  Append(SignalValue(sample, proto::POSITION_ERROR_M));
  Append(SignalValue(sample, proto::HORIZONTAL_ERROR_M));
  Append(SignalValue(sample, proto::ALTITUDE_ERROR_M));
  for (double thrust_n : sample.rotor_thrust_n) Append(thrust_n);
  for (int i = 0; i < 3; ++i) Append(sample.estimated_position_m(i));
  Append(sample.tactile_force_max_n);
  Append(sample.tactile_force_error_max_n);
  Append(sample.grasp_force_n);
  Append(sample.grasp_force_estimate_n);
  Append(sample.grasp_force_setpoint_n);
  Append(sample.load_n);
  Append(sample.load_estimate_n);
  Append(sample.object_mass_kg);
  Append(sample.servo_angle_rad);
  Append(sample.servo_command_rad);
  Append(sample.object_damaged ? 1.0 : 0.0);
  Append(sample.object_dropped ? 1.0 : 0.0);
  HILRIG_CHECK(column_ == kColumnCount, "a trace row has fewer columns than kColumnCount");
  line_[line_length_ - 1] = '\n';
  out_.write(line_.data(), static_cast<std::streamsize>(line_length_));
}

}  // namespace hilrig::host
