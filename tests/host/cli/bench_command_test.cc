#include "host/cli/bench_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kScenarios = ::hilrig::test_support::SourceDir() + "/scenarios";
constexpr std::size_t kColumns = 21;

std::vector<std::vector<std::string>> ReadCsv(const fs::path& path) {
  std::ifstream file(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(file, line)) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.push_back("");
    rows.push_back(fields);
  }
  return rows;
}

class BenchCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    out_dir_ = fs::temp_directory_path() /
               ("hilrig_bench_test_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(out_dir_);
  }
  void TearDown() override { fs::remove_all(out_dir_); }

  fs::path out_dir_;
};

std::size_t Column(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

// One test for the whole quick sweep (ctest runs every test in its own process, and the sweep
// takes seconds): the reference, 2 integrators x 2 steps, 2 field levels and the default.
TEST_F(BenchCommandTest, QuickSweepWritesOneRowPerRunAndAZeroErrorReference) {
  const CliResult result = Cli({"bench", "--quick", "--scenes", "load_ramp", "--scenarios",
                                kScenarios, "--out", out_dir_.string()});
  const auto rows = ReadCsv(out_dir_ / "work_precision.csv");

  ASSERT_EQ(result.exit_code, kExitPass) << result.err;
  // Shape: the header, the reference, 2 integrators (SIE, RK4) x 2 steps and 2 field levels, the
  // four sensor effects load_ramp has on (Earth's field, damping, saturation, encoding) each off,
  // and the default (midpoint x2 opmap:32, not one of the quick sweep's integrator points).
  ASSERT_EQ(rows.size(), 1u + 1u + 4u + 2u + 4u + 1u);
  for (const auto& row : rows) EXPECT_EQ(row.size(), kColumns);
  const auto& header = rows[0];
  EXPECT_EQ(header[0], "scene");
  EXPECT_EQ(header[14], "pareto");
  const auto& reference = rows[1];
  EXPECT_EQ(reference[Column(header, "kind")], "reference");
  EXPECT_EQ(reference[Column(header, "integrator")], "DP(1e-10)");
  EXPECT_EQ(reference[Column(header, "field_fidelity")], "tiles:16");
  EXPECT_EQ(rows.back()[Column(header, "kind")], "default");
  EXPECT_EQ(rows.back()[Column(header, "field_fidelity")], "opmap:32");
  // The reference against itself: zero error over all 300 samples (3 s at 100 Hz).
  for (const char* column : {"grasp_force_rms_error_n", "grasp_force_max_error_n",
                             "load_rms_error_n", "position_rms_error_m", "position_max_error_m"}) {
    EXPECT_EQ(reference[Column(header, column)], "0") << column;
  }
  EXPECT_EQ(reference[Column(header, "samples_compared")], "300");
  // Every other run is compared over the same samples and differs from the reference: each
  // uses a coarser field than the tiles:16 reference.
  for (std::size_t i = 2; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][Column(header, "samples_compared")], "300") << i;
    EXPECT_NE(rows[i][Column(header, "position_rms_error_m")], "0") << i;
  }
  // The effect runs name the effect they switched off, and the table says which could go.
  std::vector<std::string> effects_off;
  for (std::size_t i = 2; i < rows.size(); ++i) {
    if (rows[i][Column(header, "kind")] == "effect") {
      effects_off.push_back(rows[i][Column(header, "effect_off")]);
    } else {
      EXPECT_EQ(rows[i][Column(header, "effect_off")], "") << i;
    }
  }
  EXPECT_THAT(effects_off, ::testing::ElementsAre("earth_field", "silicone_damping",
                                                  "chip_saturation", "chip_encoding"));
  EXPECT_THAT(result.out, HasSubstr("load_ramp: each sensor effect switched off"));
  EXPECT_THAT(result.out, ::testing::ContainsRegex("chip_encoding .* (pass|FAIL) +(yes|no)"));
  // The fronts are printed and drawn.
  EXPECT_THAT(result.out, HasSubstr("load_ramp: vertical load RMS error (N), Pareto front"));
  EXPECT_THAT(result.out, HasSubstr("load_ramp: the default (midpoint x2 opmap:32"));
  // Cut to 3 s of the scene's 45, its own verdict covers only those 3 s, and says so.
  EXPECT_THAT(result.out, HasSubstr("its envelopes over the sweep's first 3 s"));
  std::ifstream svg(out_dir_ / "work_precision.svg");
  std::stringstream text;
  text << svg.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("load_ramp: grasp force error"));
  EXPECT_THAT(text.str(), HasSubstr("class=\"front\""));
}

TEST_F(BenchCommandTest, HelpNamesEveryBenchOption) {
  const CliResult help = Cli({"help", "bench"});

  for (const char* option : {"--out DIR", "--scenes a,b|all", "--scenarios DIR", "--duration-s S",
                             "--timing-repeats N", "--quick"}) {
    EXPECT_THAT(help.out, HasSubstr(option));
  }
}

TEST_F(BenchCommandTest, NegativeDurationIsBadInput) {
  const CliResult result = Cli({"bench", "--out", out_dir_.string(), "--duration-s", "-1"});

  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("--duration-s must be a positive number"));
}

TEST_F(BenchCommandTest, NaNDurationIsBadInput) {
  EXPECT_EQ(Cli({"bench", "--out", out_dir_.string(), "--duration-s", "nan"}).exit_code,
            kExitBadInput);
}

TEST_F(BenchCommandTest, TimingRepeatsOutsideOneToAThousandAreBadInput) {
  for (const char* repeats : {"0", "-3", "1001", "2.5", "x", ""}) {
    const CliResult result =
        Cli({"bench", "--out", out_dir_.string(), "--timing-repeats", repeats});

    EXPECT_EQ(result.exit_code, kExitBadInput) << repeats;
    EXPECT_THAT(result.err, HasSubstr("--timing-repeats must be a whole number")) << repeats;
  }
}

// --timing-repeats overrides --quick's single timing: every cheap run is timed that often.
TEST_F(BenchCommandTest, TimingRepeatsSetHowOftenEachRunIsTimed) {
  const CliResult result =
      Cli({"bench", "--quick", "--duration-s", "0.5", "--timing-repeats", "3", "--scenes",
           "load_ramp", "--scenarios", kScenarios, "--out", out_dir_.string()});
  const auto rows = ReadCsv(out_dir_ / "work_precision.csv");

  ASSERT_EQ(result.exit_code, kExitPass) << result.err;
  ASSERT_GT(rows.size(), 2u);
  const std::size_t timing_runs = Column(rows[0], "timing_runs");
  for (std::size_t i = 2; i < rows.size(); ++i) EXPECT_EQ(rows[i][timing_runs], "3") << i;
}

// The files are rewritten after each scene: a later scene that fails (or a Ctrl-C) leaves the
// finished ones on disk, and says so.
TEST_F(BenchCommandTest, AFailingSceneKeepsTheScenesFinishedBeforeIt) {
  fs::create_directories(out_dir_);
  const fs::path aborting = out_dir_ / "aborting.textproto";
  std::ofstream(aborting) << R"(name: "aborting"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 1 }
envelopes { name: "never" signal: ALTITUDE_ERROR_M upper: -1 abort_on_violation: true }
)";
  const CliResult result =
      Cli({"bench", "--quick", "--duration-s", "0.5", "--scenes", "hover," + aborting.string(),
           "--scenarios", kScenarios, "--out", out_dir_.string()});
  const auto rows = ReadCsv(out_dir_ / "work_precision.csv");

  EXPECT_EQ(result.exit_code, kExitCheckFailed);
  EXPECT_THAT(result.err, HasSubstr("aborting: the reference run stopped short"));
  EXPECT_THAT(result.err, HasSubstr("keeps the 1 scene(s) finished before it"));
  ASSERT_GT(rows.size(), 2u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i][0], "hover") << i;
  EXPECT_TRUE(fs::exists(out_dir_ / "work_precision.svg"));
}

TEST_F(BenchCommandTest, MissingOutIsBadInput) {
  const CliResult result = Cli({"bench", "--quick"});

  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("--out DIR is required"));
}

TEST_F(BenchCommandTest, UnknownSceneIsBadInputAndWritesNothing) {
  const CliResult result = Cli({"bench", "--quick", "--scenes", "no_such_scene", "--scenarios",
                                kScenarios, "--out", out_dir_.string()});

  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_FALSE(fs::exists(out_dir_ / "work_precision.csv"));
}

}  // namespace
}  // namespace hilrig::host
