// `hilrig run --set PATH=VALUE,...`: numbers of the spec set by field path before it is
// validated (what a sweep's failing case is reproduced with), and every way it can be wrong.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "host/cli/build_info.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(CliRunSetTest, SetsTheSpecsNumbersAndRefusesWhatItHasNot) {
  const fs::path dir = FreshTestDir("cli_run_set");
  const std::string spec = (dir / "hover.textproto").string();
  std::ofstream(spec) << "name: \"hover\"\n"
                         "vehicle { initial_position_m { z: 1 } }\n"
                         "simulation { duration_s: 1 }\n";
  const CliResult heavy = Cli({"run", spec, "--no-reference", "--out", (dir / "heavy").string(),
                               "--set", "vehicle.mass_kg=0.7,simulation.duration_s=0.5"});
  EXPECT_EQ(heavy.exit_code, 0) << heavy.err;
  EXPECT_THAT(heavy.out, HasSubstr("0.5 s simulated"));
  // The report and its page record what made the run: the build, the command, each override.
  std::ifstream report_file(dir / "heavy" / "report.json");
  const std::string report((std::istreambuf_iterator<char>(report_file)),
                           std::istreambuf_iterator<char>());
  EXPECT_THAT(report, HasSubstr("\"rig_commit\": \"" + std::string(ThisBuild().commit) + "\""));
  EXPECT_THAT(report, HasSubstr("\"build_type\": \"" + std::string(ThisBuild().build_type) + "\""));
  EXPECT_THAT(report, HasSubstr("\"command_line\": \"hilrig run " + spec +
                                " --no-reference --out " + (dir / "heavy").string() +
                                " --set vehicle.mass_kg=0.7,simulation.duration_s=0.5\""));
  EXPECT_THAT(report, HasSubstr("\"path\": \"vehicle.mass_kg\",\n    \"value\": 0.7"));
  std::ifstream page_file(dir / "heavy" / "index.html");
  const std::string page((std::istreambuf_iterator<char>(page_file)),
                         std::istreambuf_iterator<char>());
  EXPECT_THAT(page, HasSubstr("<td>--set vehicle.mass_kg</td><td class=\"num\">0.7</td>"));
  const CliResult unknown = Cli({"run", spec, "--no-reference", "--out", (dir / "x").string(),
                                 "--set", "vehicle.weight_kg=1"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_THAT(unknown.err,
              HasSubstr("\"vehicle.weight_kg\": vehicle.weight_kg: Vehicle has no field"));
  const CliResult negative = Cli({"run", spec, "--no-reference", "--out", (dir / "y").string(),
                                  "--set", "vehicle.mass_kg=-1"});
  EXPECT_EQ(negative.exit_code, 2);
  EXPECT_THAT(negative.err, HasSubstr("vehicle.mass_kg"));
  const CliResult malformed = Cli({"run", spec, "--set", "vehicle.mass_kg"});
  EXPECT_EQ(malformed.exit_code, 2);
  EXPECT_THAT(malformed.err, HasSubstr("expected PATH=VALUE"));
}

}  // namespace
}  // namespace hilrig::host
