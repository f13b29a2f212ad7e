// Loading a sweep: the scenarios it names, its axes checked against each of them, and every
// problem of the file located and reported at once.
#include "host/sweep/sweep_spec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/bottle_scene.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

std::filesystem::path FolderWithBottle(const std::string& name) {
  const std::filesystem::path dir = FreshTestDir(name);
  std::ofstream(dir / "bottle.textproto") << kBottleSceneText;
  return dir;
}

TEST(SweepSpecTest, LoadsTheScenariosRelativeToTheSweepFile) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_loads");
  std::ofstream(dir / "sweep.textproto") << R"(name: "bottle_slip"
scenario: "bottle.textproto"
seeds { count: 4 }
axis { path: "object.mass_kg" list { value: 0.18 value: 0.3 } }
axis { path: "timeline[1].grasp.force_n" grid { from: 1 to: 4 count: 4 } }
criterion { envelope: "not_dropped" min_pass_rate: 0.8 }
)";
  auto sweep = LoadSweep((dir / "sweep.textproto").string());
  ASSERT_TRUE(sweep.ok()) << sweep.error().message;
  ASSERT_EQ(sweep.value().scenarios.size(), 1u);
  EXPECT_EQ(sweep.value().scenarios[0].spec.name(), "bottle");
  EXPECT_EQ(sweep.value().scenarios[0].path, (dir / "bottle.textproto").string());
}

// Each line of the sweep below carries one mistake; each is reported at its line.
TEST(SweepSpecTest, LocatesEveryProblemAtOnce) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_problems");
  const std::string text = R"(name: "bad sweep!"
scenario: "bottle.textproto"
scenario: "missing.textproto"
seeds { count: 3 list: 7 }
axis { path: "object.weight_kg" list { value: 1 } }
axis { path: "object.fixture" list { value: 1 } }
axis { path: "vehicle.mass_kg" grid { from: 0.5 to: 0.7 } }
axis { path: "models.vio.latency_s" distribution { uniform { low: 0.05 high: 0.01 } } }
axis { path: "vehicle.linear_drag_n_s_per_m" distribution { normal { mean: 0 sigma: 1 low: 9 } } }
axis { path: "seed" list { value: 1 } }
criterion { envelope: "no_such_envelope" min_pass_rate: 0.9 }
criterion { envelope: "not_dropped" min_pass_rate: 1.5 confidence: 1 }
criterion { envelope: "not_dropped" }
)";
  auto sweep = ParseSweep(text, "s.textproto", dir.string());
  ASSERT_FALSE(sweep.ok());
  const std::string& message = sweep.error().message;
  const std::vector<std::string> expected = {
      "s.textproto:1:1: name: ",
      "s.textproto:3:1: scenario[1]: does not load:",
      "missing.textproto",
      "s.textproto:4:1: seeds: give a count or a list of seeds, not both",
      "s.textproto:5:8: axis[0].path: in ",
      "GraspObject has no field weight_kg",
      "s.textproto:6:8: axis[1].path: in ",
      "fixture is text, not a number",
      "s.textproto:7:",
      "axis[2].grid.count: must be in 1..10000",
      "s.textproto:8:",
      "axis[3].distribution.uniform: low must be below high",
      "s.textproto:9:",
      "axis[4].distribution.normal: [low, high] holds ",
      "s.textproto:10:8: axis[5].path: the seed is swept by `seeds`",
      "s.textproto:11:",
      "criterion[0].envelope: no envelope \"no_such_envelope\"",
      "criterion[1].min_pass_rate: must be in [0, 1]",
      "criterion[1].confidence: must be in (0, 1)",
      "s.textproto:13:1: criterion[2]: set min_pass_rate, quantile or both",
  };
  for (const std::string& part : expected) {
    EXPECT_THAT(message, HasSubstr(part)) << message;
  }
}

// An ablation's envelopes are expected to fail, so their margins are negative by design: a margin
// criterion must name at least one envelope expected to pass, and one that does is accepted.
TEST(SweepSpecTest, AMarginCriterionNeedsAnEnvelopeExpectedToPass) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_ablation");
  std::ofstream(dir / "ablation.textproto")
      << kBottleSceneText
      << "envelopes { name: \"holds\" signal: ALTITUDE_ERROR_M upper: 0.05 expect: FAIL }\n";
  const auto load = [&](const std::string& criterion) {
    return ParseSweep("name: \"ablation\"\nscenario: \"ablation.textproto\"\n" + criterion,
                      "a.textproto", dir.string());
  };
  const auto named = load("criterion { envelope: \"holds\" quantile: 0.5 }\n");
  ASSERT_FALSE(named.ok());
  EXPECT_THAT(named.error().message,
              HasSubstr("criterion[0].quantile: every envelope the criterion names is expected to "
                        "fail (expect: FAIL)"));
  EXPECT_TRUE(load("criterion { envelope: \"holds\" min_pass_rate: 0.2 }\n").ok());
  EXPECT_TRUE(load("criterion { quantile: 0.5 }\n").ok());  // not_dropped is expected to pass
}

// 30 cases that all pass give a Wilson lower bound of 0.886 at 95 %: a criterion of 0.9 could only
// fail, so the sweep is refused before it runs, with the 35 cases it needs; 1.0 no sweep reaches.
TEST(SweepSpecTest, RefusesAPassRateItsCasesCannotReach) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_reachable");
  const auto load = [&](int seeds, const std::string& rate) {
    return ParseSweep("name: \"s\"\nscenario: \"bottle.textproto\"\nseeds { count: " +
                          std::to_string(seeds) + " }\ncriterion { min_pass_rate: " + rate + " }\n",
                      "s.textproto", dir.string());
  };
  const auto short_of_it = load(30, "0.9");
  ASSERT_FALSE(short_of_it.ok());
  EXPECT_THAT(short_of_it.error().message,
              HasSubstr("criterion[0].min_pass_rate: cannot be met: with all 30 cases of a "
                        "scenario passing, the pass rate's lower bound at 0.95 confidence is "
                        "0.886487; it needs at least 35 cases per scenario"));
  EXPECT_TRUE(load(35, "0.9").ok());
  EXPECT_FALSE(load(34, "0.9").ok());
  const auto never = load(100, "1");
  ASSERT_FALSE(never.ok());
  EXPECT_THAT(never.error().message, HasSubstr("no number of cases reaches it"));
}

// A set must name a number of every scenario, and not one the seeds or an axis already sweep.
TEST(SweepSpecTest, SetsAreCheckedInTheFileAndFromTheCommandLine) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_sets");
  const auto load = [&](const std::string& body) {
    return ParseSweep(
        "name: \"s\"\nscenario: \"bottle.textproto\"\n"
        "axis { path: \"object.mass_kg\" list { value: 0.2 } }\n" +
            body + "criterion { min_pass_rate: 0.2 }\n",
        "s.textproto", dir.string());
  };
  const auto swept = load("set { path: \"object.mass_kg\" value: 0.3 }\n");
  ASSERT_FALSE(swept.ok());
  EXPECT_THAT(swept.error().message,
              HasSubstr("set[0]: \"object.mass_kg\" is swept by an axis, which would undo it"));
  auto sweep = load("set { path: \"vehicle.mass_kg\" value: 0.9 }\n");
  ASSERT_TRUE(sweep.ok()) << sweep.error().message;
  for (const auto& [path, why] : std::vector<std::pair<std::string, std::string>>{
           {"seed", "--set seed: the seed is swept by `seeds`, not set"},
           {"object.mass_kg", "--set object.mass_kg: \"object.mass_kg\" is swept by an axis"},
           {"vehicle.weight_kg", "--set vehicle.weight_kg: in "}}) {
    const auto added = AddSweepSets(sweep.value(), {{"vehicle.mass_kg", 1.0}, {path, 1.0}});
    ASSERT_FALSE(added.ok()) << path;
    EXPECT_THAT(added.error().message, HasSubstr(why));
    EXPECT_EQ(sweep.value().spec.set_size(), 1) << "a refused --set changes nothing";
  }
  ASSERT_TRUE(AddSweepSets(sweep.value(), {{"vehicle.mass_kg", 1.0}}).ok());
  EXPECT_EQ(sweep.value().spec.set_size(), 2);
}

TEST(SweepSpecTest, RefusesAGridThatExpandsPastTheCaseLimit) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_limit");
  auto sweep = ParseSweep(R"(name: "huge"
scenario: "bottle.textproto"
seeds { count: 1000 }
axis { path: "object.mass_kg" grid { from: 0.1 to: 1 count: 10000 } }
criterion { min_pass_rate: 0.5 }
)",
                          "huge.textproto", dir.string());
  ASSERT_FALSE(sweep.ok());
  EXPECT_THAT(sweep.error().message, HasSubstr("1e+07 cases: at most 1000000 per sweep"));
}

// Ends a double holds, whose span no double does: the points between them would not be numbers.
TEST(SweepSpecTest, RefusesAGridWhoseSpanIsNotAFiniteNumber) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_span");
  auto sweep = ParseSweep(R"(name: "wide"
scenario: "bottle.textproto"
axis { path: "object.mass_kg" grid { from: -1.7e308 to: 1.7e308 count: 3 } }
criterion { min_pass_rate: 0.5 }
)",
                          "wide.textproto", dir.string());
  ASSERT_FALSE(sweep.ok());
  EXPECT_THAT(sweep.error().message,
              HasSubstr("wide.textproto:3:31: axis[0].grid: from and to are too far apart"));
}

// A scenario path or axis path with a line break would reach failing.txt and the batch scripts.
TEST(SweepSpecTest, RefusesPathsWithControlCharacters) {
  const std::filesystem::path dir = FolderWithBottle("sweep_spec_control");
  auto sweep = ParseSweep(R"(name: "control"
scenario: "bottle.textproto\ntouch /tmp/x"
criterion { min_pass_rate: 0.5 }
)",
                          "control.textproto", dir.string());
  ASSERT_FALSE(sweep.ok());
  EXPECT_THAT(sweep.error().message,
              HasSubstr("control.textproto:2:1: scenario[0]: byte 17 starts a control character"));
}

TEST(SweepSpecTest, NeedsAScenarioAndACriterion) {
  auto sweep = ParseSweep("name: \"empty\"\n", "e.textproto", ".");
  ASSERT_FALSE(sweep.ok());
  EXPECT_THAT(sweep.error().message, HasSubstr("at least one scenario is required"));
  EXPECT_THAT(sweep.error().message, HasSubstr("at least one criterion is required"));
  auto garbled = ParseSweep("name: \"x\" axis {", "g.textproto", ".");
  ASSERT_FALSE(garbled.ok());
  EXPECT_THAT(garbled.error().message, HasSubstr("g.textproto:1:"));
}

}  // namespace
}  // namespace hilrig::host
