#include "host/trace/trace_csv.h"

#include <gtest/gtest.h>

#include <charconv>
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

TEST(TraceCsvTest, RowsHaveAsManyColumnsAsTheHeader) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  writer.Write(TraceSample{});
  std::istringstream lines(out.str());
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  EXPECT_EQ(Split(header).size(), Split(row).size());
  EXPECT_EQ(Split(header).front(), "time_s");
}

TEST(TraceCsvTest, NumbersReadBackExactly) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  TraceSample sample;
  sample.time_s = 0.1 + 0.2;
  sample.position_m = {1.0 / 3.0, -2e-17, 12345.678};
  writer.Write(sample);
  std::istringstream lines(out.str());
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  const auto fields = Split(row);
  const double expected[] = {sample.time_s, sample.position_m.x(), sample.position_m.y(),
                             sample.position_m.z()};
  for (int i = 0; i < 4; ++i) {
    double parsed = 0;
    std::from_chars(fields[i].data(), fields[i].data() + fields[i].size(), parsed);
    EXPECT_EQ(parsed, expected[i]) << fields[i];
  }
}

TEST(TraceCsvTest, ErrorColumnsAreComputedFromPositionAndReference) {
  std::ostringstream out;
  TraceCsvWriter writer(out);
  TraceSample sample;
  sample.position_m = {3, 4, 1};
  sample.reference_m = {0, 0, 2};
  writer.Write(sample);
  std::istringstream lines(out.str());
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
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
  sample.time_s = 0.5;  // x and z repeat, y changes from -0 to +0 (other bits, other text)
  sample.position_m.y() = 0.0;
  writer.Write(sample);
  std::istringstream lines(out.str());
  std::string header, first, second;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  const auto a = Split(first);
  const auto b = Split(second);
  EXPECT_EQ(a[0], "0.25");
  EXPECT_EQ(b[0], "0.5");
  EXPECT_EQ(a[1], "0.5");
  EXPECT_EQ(b[1], "0.5");
  EXPECT_EQ(a[2], "-0");
  EXPECT_EQ(b[2], "0");
  EXPECT_EQ(b[3], "7");
  EXPECT_EQ(b.size(), Split(header).size());
}

}  // namespace
}  // namespace hilrig::host
