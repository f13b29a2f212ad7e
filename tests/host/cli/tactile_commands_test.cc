#include "host/cli/tactile_commands.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/cli/cli.h"
#include "host/scenario/scenario_config.h"
#include "rig/file_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/shared_calibration.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path& CalibrationDir() { return SharedCalibrationDir(); }
std::string CalibrationFile() { return SharedCalibrationFile(); }

constexpr std::size_t kMaxPageBytes = std::size_t{1} << 20;

TEST(TactileCommandsTest, CalibratePrintsConstantsAndResidualsAndWritesTheFile) {
  ASSERT_TRUE(fs::exists(CalibrationFile()));
  std::ifstream file(CalibrationFile());
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("published_film"));
  EXPECT_THAT(text.str(), HasSubstr("node_id: 6"));
}

TEST(TactileCommandsTest, AccuracyWritesBothConditions) {
  const fs::path out = CalibrationDir() / "accuracy";
  const CliResult result = Cli(
      {"accuracy", "--calibration", CalibrationFile(), "--out", out.string(), "--field", "map:16"});
  ASSERT_EQ(result.exit_code, kExitPass) << result.err;
  EXPECT_THAT(result.out, HasSubstr("compensated"));
  std::ifstream file(out / "accuracy.json");
  std::stringstream json;
  json << file.rdbuf();
  EXPECT_THAT(json.str(), HasSubstr("\"condition\": \"uncompensated\""));
  EXPECT_THAT(json.str(), HasSubstr("\"rmse_n\""));
  // Without --dut-filter the sweep decodes through the filter a scene's DUT has.
  EXPECT_THAT(json.str(),
              HasSubstr("\"dut_filter_samples\": " + std::to_string(kDefaultForceAverageSamples)));
  // The page beside it grades the condition the sweep names compensated.
  EXPECT_THAT(result.out, HasSubstr("wrote " + (out / "accuracy.html").string()));
  const auto page = rig::ReadRegularFile((out / "accuracy.html").string(), kMaxPageBytes);
  ASSERT_TRUE(page) << page.error().message;
  EXPECT_THAT(page.value(), HasSubstr("<svg"));
  EXPECT_THAT(page.value(), Not(HasSubstr("no compensated condition")));
}

// --budget calibrates and measures each configuration itself: no --calibration needed.
TEST(TactileCommandsTest, AccuracyBudgetWritesEveryConfiguration) {
  const fs::path out = CalibrationDir() / "budget";
  const CliResult result = Cli(
      {"accuracy", "--budget", "--out", out.string(), "--field", "map:16", "--dut-filter", "2"});
  ASSERT_EQ(result.exit_code, kExitPass) << result.err;
  EXPECT_THAT(result.out, HasSubstr("only chip_noise"));
  EXPECT_THAT(result.out, HasSubstr("decoder alone (exact field)"));
  EXPECT_THAT(result.err, HasSubstr("calibrating and measuring with all but earth_field"));
  std::ifstream file(out / "budget.json");
  std::stringstream json;
  json << file.rdbuf();
  EXPECT_THAT(json.str(), HasSubstr("\"configuration\": \"all + silicone_stiffening\""));
  EXPECT_THAT(json.str(), HasSubstr("\"p95_n\""));
  EXPECT_THAT(json.str(), HasSubstr("\"gap_rmse_n\""));
  EXPECT_THAT(json.str(), HasSubstr("\"dut_filter_samples\": 2"));
  EXPECT_THAT(result.out, HasSubstr("wrote " + (out / "budget.html").string()));
  const auto page = rig::ReadRegularFile((out / "budget.html").string(), kMaxPageBytes);
  ASSERT_TRUE(page) << page.error().message;
  EXPECT_THAT(page.value(), HasSubstr("<svg"));
  EXPECT_THAT(page.value(), HasSubstr("all + silicone_stiffening"));
}

TEST(TactileCommandsTest, DecodePrintsSOrAFlagPerLine) {
  const CliResult result = Cli({"decode", "--calibration", CalibrationFile()},
                               "0.0001 -0.0002 0.0035\n"
                               "nan 0 0.003\n"
                               "0 0 3.5\n"
                               "1 2\n");
  const std::vector<std::string> expected_starts = {
      "", "invalid non_finite_input", "invalid out_of_range", "invalid malformed_line"};
  std::istringstream lines(result.out);
  std::string line;
  std::getline(lines, line);
  double sx = 0, sy = 0, sz = 0;
  EXPECT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf", &sx, &sy, &sz), 3) << line;
  for (std::size_t i = 1; i < expected_starts.size(); ++i) {
    std::getline(lines, line);
    EXPECT_EQ(line, expected_starts[i]);
  }
  EXPECT_EQ(result.exit_code, kExitBadInput);  // the malformed line
}

TEST(TactileCommandsTest, DecodeOfCleanInputExitsZero) {
  EXPECT_EQ(Cli({"decode", "--calibration", CalibrationFile()}, "0 0 0.003\n").exit_code,
            kExitPass);
}

TEST(TactileCommandsTest, DecodeStopsAtALineLongerThanAnyReadingAndNamesIt) {
  const CliResult result = Cli({"decode", "--calibration", CalibrationFile()},
                               "0 0 0.003\n" + std::string(5000, '7') + "\n0 0 0.003\n");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("line 2: longer than 4096 bytes"));
  EXPECT_EQ(std::count(result.out.begin(), result.out.end(), '\n'), 1) << result.out;
}

TEST(TactileCommandsTest, DecodeOfAnInputWithoutNewlinesStopsAtTheCap) {
  // As /dev/zero on stdin would be: the first line never ends.
  const CliResult result =
      Cli({"decode", "--calibration", CalibrationFile()}, std::string(std::size_t{1} << 20, '\0'));
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("line 1: longer than 4096 bytes"));
  EXPECT_EQ(result.out, "");
}

TEST(TactileCommandsTest, DecodeTakesALineOfExactlyTheCap) {
  std::string line = "0 0 0.003";
  line += std::string(4096 - line.size(), ' ');
  const CliResult result = Cli({"decode", "--calibration", CalibrationFile()}, line + "\n");
  EXPECT_EQ(result.exit_code, kExitPass) << result.err;
}

TEST(TactileCommandsTest, DecodeStopsReadingOnceItsAnswersCannotBeWritten) {
  const int full_device = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  ASSERT_GE(full_device, 0);
  rig::FdStreamBuf full(full_device, 0);  // unbuffered: the first answer fails
  std::ostream out(&full);
  std::ostringstream err;
  std::string readings;
  for (int i = 0; i < 1000; ++i) readings += "0 0 0.003\n";
  std::istringstream in(readings);
  EXPECT_EQ(RunCli({"decode", "--calibration", CalibrationFile()}, out, err, nullptr, &in),
            kExitBadInput);
  EXPECT_EQ(full.error_number(), ENOSPC);
  EXPECT_FALSE(in.eof()) << "read all " << readings.size() << " bytes";
  EXPECT_LT(in.tellg(), std::streampos(100));
}

TEST(TactileCommandsTest, BadInvocationsExitTwoWithAReason) {
  EXPECT_THAT(Cli({"calibrate"}).err, HasSubstr("--out DIR is required"));
  EXPECT_EQ(Cli({"accuracy", "--out", "/tmp/x"}).exit_code, kExitBadInput);
  EXPECT_THAT(Cli({"decode", "--calibration", "/nonexistent.textproto"}).err,
              HasSubstr("cannot read /nonexistent.textproto: No such file or directory"));
  EXPECT_THAT(Cli({"calibrate", "--out", "/tmp/x", "--field", "tiles:0"}).err,
              HasSubstr("tiles per side"));
  EXPECT_THAT(Cli({"calibrate", "--out", "/tmp/x", "--field", "magic"}).err,
              HasSubstr("unknown field fidelity"));
}

TEST(TactileCommandsTest, DecodeRejectsAFileThatIsNotACalibration) {
  const fs::path bogus = fs::path(::testing::TempDir()) / "bogus.textproto";
  std::ofstream(bogus) << "this is not { a calibration";
  EXPECT_EQ(Cli({"decode", "--calibration", bogus.string()}).exit_code, kExitBadInput);
}

}  // namespace
}  // namespace hilrig::host
