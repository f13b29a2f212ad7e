#include "host/trace/trace_csv.h"

#include <gtest/gtest.h>

#include <charconv>
#include <limits>
#include <sstream>

namespace hilrig::host {
namespace {

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  return fields;
}

// The header line and the first row of a trace that holds `sample` alone.
struct HeaderAndRow {
  std::string header;
  std::string row;
};

HeaderAndRow WriteOne(const TraceSample& sample) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  writer.Write(sample);
  std::istringstream lines(out.str());
  HeaderAndRow written;
  std::getline(lines, written.header);
  std::getline(lines, written.row);
  return written;
}

TEST(TraceCsvTest, RowsHaveAsManyColumnsAsTheHeader) {
  const HeaderAndRow written = WriteOne(TraceSample{});
  EXPECT_EQ(Split(written.header).size(), Split(written.row).size());
  EXPECT_EQ(Split(written.header).front(), "time_s");
}

// The rows' numbers have 9 significant digits: within one unit in the 9th digit of the double.
TEST(TraceCsvTest, NumbersHaveNineSignificantDigits) {
  TraceSample sample;
  sample.time_s = 0.1 + 0.2;
  sample.position_m = {1.0 / 3.0, -2e-17, 12345.678};
  sample.reference_m = {-2.0 / 3.0, 1234567890123.0, 0.000123456789123};
  const auto fields = Split(WriteOne(sample).row);
  const std::vector<std::string> expected = {"0.3",           "0.333333333",  "-2e-17",
                                             "12345.678",     "-0.666666667", "1.23456789e+12",
                                             "0.000123456789"};
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(fields[i], expected[i]);
  double parsed = 0;
  std::from_chars(fields[1].data(), fields[1].data() + fields[1].size(), parsed);
  EXPECT_NEAR(parsed, 1.0 / 3.0, 1e-9);  // one unit in the 9th digit of 0.333...
}

TEST(TraceCsvTest, NonFiniteValuesAreSpelledNanAndInf) {
  TraceSample sample;
  sample.position_m = {std::numeric_limits<double>::quiet_NaN(),
                       std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity()};
  const auto fields = Split(WriteOne(sample).row);
  EXPECT_EQ(fields[1], "nan");
  EXPECT_EQ(fields[2], "inf");
  EXPECT_EQ(fields[3], "-inf");
}

TEST(TraceCsvTest, HeaderNamesEveryColumnInOrder) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  EXPECT_EQ(out.str(),
            "time_s,x_m,y_m,z_m,ref_x_m,ref_y_m,ref_z_m,vx_m_s,vy_m_s,vz_m_s,roll_deg,pitch_deg,"
            "yaw_deg,tilt_deg,position_error_m,horizontal_error_m,altitude_error_m,thrust0_n,"
            "thrust1_n,thrust2_n,thrust3_n,est_x_m,est_y_m,est_z_m,tactile_force_max_n,"
            "tactile_force_error_max_n,grasp_force_n,grasp_force_estimate_n,"
            "grasp_force_setpoint_n,load_n,load_estimate_n,object_mass_kg,servo_angle_rad,"
            "servo_command_rad,object_damaged,object_dropped,ground_force_n,object_held,"
            "slip_speed_m_s,pad0_force_n,pad1_force_n,pad2_force_n,pad3_force_n,pad4_force_n,"
            "pad5_force_n,pad0_force_estimate_n,pad1_force_estimate_n,pad2_force_estimate_n,"
            "pad3_force_estimate_n,pad4_force_estimate_n,pad5_force_estimate_n\n");
  EXPECT_EQ(Split(out.str()).size(), TraceCsvWriter::kColumnCount);
}

// Every column in its place: each gets a distinct value and the row must list them in header
// order.
TEST(TraceCsvTest, EveryFieldLandsInItsColumn) {
  TraceSample s;
  s.time_s = 1;
  s.position_m = {2, 3, 4};
  s.reference_m = {2, 3, 5};
  s.velocity_m_s = {6, 7, 8};
  s.roll_pitch_yaw_deg = {9, 10, 11};
  s.tilt_deg = 12;
  s.rotor_thrust_n = {13, 14, 15, 16};
  s.estimated_position_m = {17, 18, 19};
  s.tactile_force_max_n = 20;
  s.tactile_force_error_max_n = 21;
  s.grasp_force_n = 22;
  s.grasp_force_estimate_n = 23;
  s.grasp_force_setpoint_n = 24;
  s.load_n = 25;
  s.load_estimate_n = 26;
  s.object_mass_kg = 27;
  s.servo_angle_rad = 28;
  s.servo_command_rad = 29;
  s.object_damaged = true;
  s.ground_force_n = 30;
  s.object_held = true;
  s.slip_speed_m_s = 31;
  s.pad_force_n = {32, 33, 34, 35, 36, 37};
  s.pad_force_estimate_n = {38, 39, 40, 41, 42, 43};
  s.pad_force_error_n = {99, 99, 99, 99, 99, 99};  // a signal, not a column
  EXPECT_EQ(WriteOne(s).row,
            "1,2,3,4,2,3,5,6,7,8,9,10,11,12,1,0,1,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,"
            "29,1,0,30,1,31,32,33,34,35,36,37,38,39,40,41,42,43");
}

TEST(TraceCsvTest, ErrorColumnsAreComputedFromPositionAndReference) {
  TraceSample sample;
  sample.position_m = {3, 4, 1};
  sample.reference_m = {0, 0, 2};
  const auto [header, row] = WriteOne(sample);
  const auto names = Split(header);
  const auto values = Split(row);
  const auto column = [&](const std::string& name) {
    return values[std::find(names.begin(), names.end(), name) - names.begin()];
  };
  EXPECT_EQ(column("horizontal_error_m"), "5");
  EXPECT_EQ(column("altitude_error_m"), "1");
}

TEST(TraceCsvTest, ARepeatedColumnIsWrittenAgainAndAChangedOneAnew) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  TraceSample sample;
  sample.time_s = 0.25;
  sample.position_m = {0.5, -0.0, 7};
  writer.Write(sample);
  sample.time_s = 0.5;  // x and z repeat, y changes from -0 to 2.5
  sample.position_m.y() = 2.5;
  writer.Write(sample);
  sample.position_m.y() = 0.0;  // +0 after -0 and 2.5: other bits, the same text
  writer.Write(sample);
  std::istringstream lines(out.str());
  std::string header, first, second, third;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  std::getline(lines, third);
  const auto a = Split(first);
  const auto b = Split(second);
  const auto c = Split(third);
  EXPECT_EQ(a[0], "0.25");
  EXPECT_EQ(b[0], "0.5");
  EXPECT_EQ(a[1], "0.5");
  EXPECT_EQ(b[1], "0.5");
  EXPECT_EQ(a[2], "0");  // -0 is written as 0
  EXPECT_EQ(b[2], "2.5");
  EXPECT_EQ(c[2], "0");
  EXPECT_EQ(b[3], "7");
  EXPECT_EQ(b.size(), Split(header).size());
  EXPECT_EQ(c.size(), Split(header).size());
}

}  // namespace
}  // namespace hilrig::host
