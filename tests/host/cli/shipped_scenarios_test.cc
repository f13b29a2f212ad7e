// Every scenario `./scripts/run` runs (scenarios/*.textproto) meets every expected verdict in the
// run it ships with: its default fidelity, noise on, its own seed, lockstep. A sweep that puts a
// default on the Pareto front judges it with noise off; this is the run users get. Each scene is a
// test of its own (`--no-reference`: the reference comparison has tests of its own).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ShippedScenes() {
  std::vector<std::string> scenes;
  for (const auto& entry :
       fs::directory_iterator(fs::path(::hilrig::test_support::SourceDir()) / "scenarios")) {
    if (entry.is_regular_file() && entry.path().extension() == ".textproto") {
      scenes.push_back(entry.path().stem().string());
    }
  }
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

class ShippedScenarioTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedScenarioTest, MeetsEveryExpectedVerdict) {
  const fs::path out = FreshTestDir("hilrig_shipped_" + GetParam() + "_");
  const std::string spec =
      (fs::path(::hilrig::test_support::SourceDir()) / "scenarios" / (GetParam() + ".textproto"))
          .string();

  const CliResult run = Cli({"run", spec, "--no-reference", "--out", out.string()});

  EXPECT_EQ(run.exit_code, kExitPass) << run.out << run.err;
  EXPECT_NE(run.out.find("completed"), std::string::npos) << run.out;
  fs::remove_all(out);
}

TEST(ShippedScenariosTest, TheSuiteIsThere) { EXPECT_GE(ShippedScenes().size(), 10u); }

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScenarioTest, ::testing::ValuesIn(ShippedScenes()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace hilrig::host
