// A sweep's cases: the order, the seeds, grid points with exact ends, draws that depend on the
// case alone, and a case whose values make an invalid scenario named with its values.
#include "host/sweep/sweep_cases.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

// A scene's body; each scene's name goes before it.
constexpr const char* kSceneBody = R"(seed: 40
simulation { duration_s: 2 }
vehicle { initial_position_m { z: 1 } }
models { tactile { enabled: true } }
object { fixture: "water_bottle" }
timeline { at_s: 1 grasp { force_n: 3.5 } }
envelopes { name: "not_dropped" signal: OBJECT_DROPPED upper: 0 }
)";

LoadedSweep Sweep(const std::string& name, const std::string& body) {
  const std::filesystem::path dir = FreshTestDir(name);
  for (const char* scene : {"a", "b"}) {
    std::ofstream(dir / (std::string(scene) + ".textproto")) << "name: \"" << scene << "\"\n"
                                                             << kSceneBody;
  }
  const std::string text =
      std::string("name: \"s\"\n").append(body).append("criterion { min_pass_rate: 0.2 }\n");
  auto sweep = ParseSweep(text, "s.textproto", dir.string());
  EXPECT_TRUE(sweep.ok()) << sweep.error().message;
  return sweep.ok() ? std::move(sweep).value() : LoadedSweep{};
}

TEST(SweepCasesTest, ScenariosThenPointsThenSeedsTheLastAxisFastest) {
  const LoadedSweep sweep = Sweep("sweep_cases_order", R"(scenario: "a.textproto"
scenario: "b.textproto"
seeds { count: 2 first: 5 }
axis { path: "object.mass_kg" list { value: 0.1 value: 0.2 } }
axis { path: "timeline[0].grasp.force_n" grid { from: 1 to: 3 count: 3 } }
)");
  ASSERT_EQ(CaseCount(sweep), 2u * 2 * 3 * 2);
  const SweepCaseSpace cases(sweep);
  ASSERT_EQ(cases.case_count(), CaseCount(sweep));
  const SweepCase first = cases.CaseAt(0);
  EXPECT_EQ(first.scenario, 0u);
  EXPECT_EQ(first.seed, 5u);
  EXPECT_EQ(first.values, (std::vector<double>{0.1, 1}));
  EXPECT_EQ(cases.CaseAt(1).seed, 6u);
  EXPECT_EQ(cases.CaseAt(2).values, (std::vector<double>{0.1, 2}));
  EXPECT_EQ(cases.CaseAt(6).values, (std::vector<double>{0.2, 1}));
  const SweepCase last = cases.CaseAt(23);
  EXPECT_EQ(last.scenario, 1u);
  EXPECT_EQ(last.seed, 6u);
  EXPECT_EQ(last.values, (std::vector<double>{0.2, 3}));
  // Each value's place among its axis's points: what the sweep page's map files the case under.
  EXPECT_EQ(first.point_index, (std::vector<std::size_t>{0, 0}));
  EXPECT_EQ(cases.CaseAt(2).point_index, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(last.point_index, (std::vector<std::size_t>{1, 2}));
  auto scenario = CaseScenario(sweep, last);
  ASSERT_TRUE(scenario.ok()) << scenario.error().message;
  EXPECT_EQ(scenario.value().name(), "b");
  EXPECT_EQ(scenario.value().seed(), 6u);
  EXPECT_EQ(scenario.value().object().mass_kg(), 0.2);
  EXPECT_EQ(scenario.value().timeline(0).grasp().force_n(), 3);
}

// A sweep's `set` reaches every case before its axes: the vehicle's mass set, the object's swept.
TEST(SweepCasesTest, SetsReachEveryCaseBeforeTheAxes) {
  LoadedSweep sweep = Sweep("sweep_cases_sets", R"(scenario: "a.textproto"
axis { path: "object.mass_kg" list { value: 0.1 value: 0.2 } }
set { path: "vehicle.mass_kg" value: 0.9 }
)");
  ASSERT_TRUE(AddSweepSets(sweep, {{"timeline[0].grasp.force_n", 2.5}}).ok());
  const SweepCaseSpace cases(sweep);
  for (std::uint64_t i = 0; i < cases.case_count(); ++i) {
    auto scenario = CaseScenario(sweep, cases.CaseAt(i));
    ASSERT_TRUE(scenario.ok()) << scenario.error().message;
    EXPECT_EQ(scenario.value().vehicle().mass_kg(), 0.9);
    EXPECT_EQ(scenario.value().timeline(0).grasp().force_n(), 2.5);
    EXPECT_EQ(scenario.value().object().mass_kg(), cases.CaseAt(i).values[0]);
  }
}

TEST(SweepCasesTest, WithoutSeedsEachScenarioKeepsItsOwn) {
  const LoadedSweep sweep = Sweep("sweep_cases_own_seed", "scenario: \"a.textproto\"\n");
  ASSERT_EQ(CaseCount(sweep), 1u);
  EXPECT_EQ(SweepCaseSpace(sweep).CaseAt(0).seed, 40u);
}

TEST(SweepCasesTest, GridEndsAreExactAndLogGridsSpaceByRatio) {
  proto::Axis axis;
  axis.mutable_grid()->set_from(0.1);
  axis.mutable_grid()->set_to(0.7);
  axis.mutable_grid()->set_count(7);
  const std::vector<double> linear = AxisPoints(axis);
  ASSERT_EQ(linear.size(), 7u);
  EXPECT_EQ(linear.front(), 0.1);
  EXPECT_EQ(linear.back(), 0.7);
  EXPECT_NEAR(linear[3], 0.4, 1e-15);
  axis.mutable_grid()->set_from(1);
  axis.mutable_grid()->set_to(1000);
  axis.mutable_grid()->set_count(4);
  axis.mutable_grid()->set_log(true);
  const std::vector<double> log = AxisPoints(axis);
  EXPECT_EQ(log.front(), 1);
  EXPECT_NEAR(log[1], 10, 1e-12);
  EXPECT_NEAR(log[2], 100, 1e-10);
  EXPECT_EQ(log.back(), 1000);
  axis.mutable_grid()->set_count(1);
  EXPECT_EQ(AxisPoints(axis), std::vector<double>{1});
}

// A draw depends on the seed and the axis only: the same in every scenario and at every grid
// point, different across seeds, inside its bounds, and spread like its distribution.
TEST(SweepCasesTest, DrawsDependOnTheCaseAloneAndFollowTheirDistribution) {
  const LoadedSweep sweep = Sweep("sweep_cases_draws", R"(scenario: "a.textproto"
scenario: "b.textproto"
seeds { count: 2000 }
axis { path: "timeline[0].grasp.force_n" list { value: 2 value: 3 } }
axis { path: "object.mass_kg" distribution { normal { mean: 0.2 sigma: 0.05 low: 0.1 } } }
axis { path: "object.stiffness_scale" distribution { log_uniform { low: 0.5 high: 2 } } }
axis { path: "models.vio.latency_s" distribution { uniform { low: 0.01 high: 0.05 } } }
)");
  const SweepCaseSpace cases(sweep);
  const std::uint64_t per_scenario = cases.case_count() / 2;
  double mass_sum = 0;
  double below_one_stiffness = 0;
  std::set<double> latencies;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const SweepCase c = cases.CaseAt(i);
    const SweepCase other_point = cases.CaseAt(i + 2000);
    const SweepCase other_scenario = cases.CaseAt(i + per_scenario);
    ASSERT_EQ(c.seed, other_point.seed);
    EXPECT_NE(c.values[0], other_point.values[0]);
    for (int a = 1; a < 4; ++a) {
      EXPECT_EQ(c.values[a], other_point.values[a]);
      EXPECT_EQ(c.values[a], other_scenario.values[a]);
    }
    EXPECT_GE(c.values[1], 0.1);
    EXPECT_GE(c.values[2], 0.5);
    EXPECT_LE(c.values[2], 2);
    EXPECT_GE(c.values[3], 0.01);
    EXPECT_LT(c.values[3], 0.05);
    mass_sum += c.values[1];
    below_one_stiffness += c.values[2] < 1 ? 1 : 0;
    latencies.insert(c.values[3]);
  }
  EXPECT_NEAR(mass_sum / 2000, 0.2, 0.005);            // the truncation at -2 sigma shifts 0.1 %
  EXPECT_NEAR(below_one_stiffness / 2000, 0.5, 0.05);  // log-uniform: half below the middle ratio
  EXPECT_EQ(latencies.size(), 2000u);
}

TEST(SweepCasesTest, ACaseThatMakesAnInvalidScenarioIsNamedWithItsValues) {
  const LoadedSweep sweep = Sweep("sweep_cases_invalid", R"(scenario: "a.textproto"
axis { path: "object.mass_kg" list { value: 0.2 value: -1 } }
)");
  ASSERT_EQ(CaseCount(sweep), 2u);
  const SweepCaseSpace cases(sweep);
  EXPECT_TRUE(CaseScenario(sweep, cases.CaseAt(0)).ok());
  auto invalid = CaseScenario(sweep, cases.CaseAt(1));
  ASSERT_FALSE(invalid.ok());
  EXPECT_THAT(invalid.error().message, HasSubstr("case 1 (a, seed 40, object.mass_kg=-1): "));
  EXPECT_THAT(invalid.error().message, HasSubstr("object.mass_kg"));
}

}  // namespace
}  // namespace hilrig::host
