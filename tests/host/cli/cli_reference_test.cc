// `hilrig run` compares every completed run with its scene's reference run, which it keeps in a
// cache per build: the first run makes the reference, the next reads it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class CliReferenceTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = FreshTestDir("hilrig_cli_reference_"); }
  // A short hover, so that the reference run stays quick.
  fs::path ShortHover() {
    const fs::path path = dir_ / "short_hover.textproto";
    std::ofstream(path) << R"(name: "short_hover"
seed: 3
vehicle { mass_kg: 0.556 initial_position_m { z: 1 } }
simulation { duration_s: 3 physics_rate_hz: 1000 trace_rate_hz: 100 }
timeline { at_s: 1 setpoint { position_m { x: 0.1 z: 1.0 } transition_s: 1 } }
envelopes { name: "hover" signal: POSITION_ERROR_M upper: 0.05 }
)";
    return path;
  }
  CliResult Run(const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"run",
                                     ShortHover().string(),
                                     "--out",
                                     (dir_ / "out").string(),
                                     "--reference-cache",
                                     (dir_ / "cache").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return Cli(args);
  }
  fs::path dir_;
};

TEST_F(CliReferenceTest, TheFirstRunMakesTheReferenceAndTheSecondReadsItBack) {
  const CliResult first = Run({});
  const CliResult second = Run({});

  ASSERT_EQ(first.exit_code, kExitPass) << first.err;
  ASSERT_EQ(second.exit_code, kExitPass) << second.err;
  EXPECT_THAT(first.err, HasSubstr("running the reference (DP(1e-10) x8 tiles:64)"));
  EXPECT_THAT(first.out, HasSubstr("fidelity error vs reference DP(1e-10) x8 tiles:64: position"));
  EXPECT_THAT(second.err, Not(HasSubstr("running the reference")));
  EXPECT_THAT(second.out, HasSubstr("tiles:64 (cached): position RMS"));
  const std::string report = ReadFile(dir_ / "out" / "report.json");
  EXPECT_THAT(report, HasSubstr("\"fidelity_error\""));
  EXPECT_THAT(report, HasSubstr("\"samples_compared\": \"300\""));  // 3 s at 100 Hz
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "cache"), fs::directory_iterator()), 1);
}

TEST_F(CliReferenceTest, NoReferenceLeavesTheFidelityErrorOut) {
  const CliResult result = Run({"--no-reference"});

  ASSERT_EQ(result.exit_code, kExitPass) << result.err;
  EXPECT_THAT(result.out, Not(HasSubstr("fidelity error")));
  EXPECT_THAT(ReadFile(dir_ / "out" / "report.json"), Not(HasSubstr("fidelity_error")));
  EXPECT_FALSE(fs::exists(dir_ / "cache"));
}

TEST_F(CliReferenceTest, ContradictoryReferenceFlagsAreBadInput) {
  const CliResult result = Run({"--reference", "--no-reference"});

  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("contradict"));
}

TEST_F(CliReferenceTest, ADamagedCacheEntryIsRebuiltNotRead) {
  ASSERT_EQ(Run({}).exit_code, kExitPass);
  for (const auto& entry : fs::directory_iterator(dir_ / "cache")) {
    std::ofstream(entry.path(), std::ios::trunc) << "damaged";
  }

  const CliResult again = Run({});

  ASSERT_EQ(again.exit_code, kExitPass) << again.err;
  EXPECT_THAT(again.err, HasSubstr("running the reference"));
  EXPECT_THAT(again.out, HasSubstr("fidelity error vs reference DP(1e-10) x8 tiles:64: position"));
}

// The "fidelity error vs reference ..." line of a run's output.
std::string FidelityLine(const std::string& out) {
  const auto start = out.find("fidelity error vs reference");
  return start == std::string::npos ? "" : out.substr(start, out.find('\n', start) - start);
}

// One bit of a stored position changed (a reference that reads whole): the entry is not used, the
// reference is run again, and the run reports the same error as a run without the cache.
TEST_F(CliReferenceTest, AChangedByteInTheReferenceIsMadeAgainToTheSameError) {
  const CliResult cold = Run({});
  ASSERT_EQ(cold.exit_code, kExitPass) << cold.err;
  ASSERT_NE(FidelityLine(cold.out), "");
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir_ / "cache")) {
    if (entry.path().extension() == ".ref") entries.push_back(entry.path());
  }
  ASSERT_EQ(entries.size(), 1u);
  ChangeByteFromEnd(entries[0], 17,
                    0x01);  // the last sample's z, in its exponent: 1 m becomes 15 um

  const CliResult again = Run({});

  ASSERT_EQ(again.exit_code, kExitPass) << again.err;
  EXPECT_THAT(again.err, HasSubstr("running the reference"));
  EXPECT_THAT(again.err, HasSubstr(entries[0].string() + ": the checksum does not match"));
  EXPECT_EQ(FidelityLine(again.out), FidelityLine(cold.out));
}

}  // namespace
}  // namespace hilrig::host
