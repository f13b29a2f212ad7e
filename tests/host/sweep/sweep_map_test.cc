// A sweep's pass map: the first two axes with points chosen, each case counted at its point
// whatever its seed, scenario or further axes' values, and no map for a sweep over one axis.
#include "host/sweep/sweep_map.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

void AddListAxis(proto::Sweep& spec, const std::string& path, std::vector<double> values) {
  proto::Axis* axis = spec.add_axis();
  axis->set_path(path);
  for (const double value : values) axis->mutable_list()->add_value(value);
}

void AddDistributionAxis(proto::Sweep& spec, const std::string& path) {
  proto::Axis* axis = spec.add_axis();
  axis->set_path(path);
  axis->mutable_distribution()->mutable_uniform()->set_low(0);
  axis->mutable_distribution()->mutable_uniform()->set_high(1);
}

// A sweep of one scenario over `seeds` seeds; its axes are added by each test.
LoadedSweep Sweep(std::uint32_t seeds) {
  LoadedSweep sweep;
  sweep.spec.set_name("hover_grid");
  sweep.spec.mutable_seeds()->set_count(seeds);
  SweepScenario scenario;
  scenario.spec.set_name("hover");
  sweep.scenarios.push_back(std::move(scenario));
  return sweep;
}

proto::SweepCaseResult Row(std::uint64_t index, bool passed) {
  proto::SweepCaseResult row;
  row.set_index(index);
  row.set_outcome(passed ? proto::SweepCaseResult::PASSED : proto::SweepCaseResult::FAILED);
  return row;
}

TEST(SweepMapTest, TheMapTakesTheFirstTwoAxesWithPoints) {
  proto::Sweep spec;
  AddListAxis(spec, "vehicle.mass_kg", {0.5, 0.6});
  EXPECT_FALSE(SweepMapAxes(spec).has_value());  // one axis: no map
  AddDistributionAxis(spec, "models.vio.latency_s");
  EXPECT_FALSE(SweepMapAxes(spec).has_value());  // a distribution makes no grid
  AddListAxis(spec, "envelopes[0].upper", {0.05, 1});
  AddListAxis(spec, "simulation.duration_s", {1, 2});
  EXPECT_EQ(SweepMapAxes(spec), (std::pair{0, 2}));
}

// Mass across (2 values), bound up (3 values), a third axis and 2 seeds: 4 cases a point.
TEST(SweepMapTest, EachCaseCountsAtItsPointWhateverItsSeedAndFurtherAxes) {
  LoadedSweep sweep = Sweep(2);
  AddListAxis(sweep.spec, "vehicle.mass_kg", {0.5, 0.6});
  AddListAxis(sweep.spec, "envelopes[0].upper", {0.01, 0.05, 0.05});  // a value listed twice
  AddListAxis(sweep.spec, "simulation.duration_s", {1, 2});
  // Case order: mass, then bound, then duration, then seed, the last fastest: 6 cases a mass,
  // 2 a (mass, bound, duration). At mass 0.5 the cases of bound 0.01 fail and the others pass;
  // at mass 0.6 one case in four passes, but at the second 0.05, where all do; case 23 did not
  // finish.
  std::vector<proto::SweepCaseResult> results;
  for (std::uint64_t index = 0; index < 23; ++index) {
    const bool mass_06 = index >= 12;
    const std::uint64_t bound = index % 12 / 4;
    results.push_back(Row(index, bound == 2 || (mass_06 ? index % 4 == 0 : bound == 1)));
  }
  results.push_back(Row(99, true));  // not a case of the sweep: left out

  const std::optional<GridMap> map = SweepPassMap(sweep, results);
  ASSERT_TRUE(map.has_value());
  EXPECT_EQ(map->title, "hover_grid: cases passed");
  EXPECT_EQ(map->x_label, "vehicle.mass_kg");
  EXPECT_EQ(map->y_label, "envelopes[0].upper");
  EXPECT_THAT(map->columns, ElementsAre("0.5", "0.6"));
  EXPECT_THAT(map->rows, ElementsAre("0.01", "0.05", "0.05"));
  ASSERT_EQ(map->cells.size(), 6u);
  const auto cell = [&](std::size_t column, std::size_t row) {
    const GridMapCell& at = map->cells[row * 2 + column];
    return std::pair{at.passed, at.cases};
  };
  EXPECT_EQ(cell(0, 0), (std::pair<std::uint64_t, std::uint64_t>{0, 4}));
  EXPECT_EQ(cell(0, 1), (std::pair<std::uint64_t, std::uint64_t>{4, 4}));
  EXPECT_EQ(cell(0, 2), (std::pair<std::uint64_t, std::uint64_t>{4, 4}));
  EXPECT_EQ(cell(1, 0), (std::pair<std::uint64_t, std::uint64_t>{1, 4}));
  EXPECT_EQ(cell(1, 1), (std::pair<std::uint64_t, std::uint64_t>{1, 4}));
  EXPECT_EQ(cell(1, 2), (std::pair<std::uint64_t, std::uint64_t>{3, 3}));  // case 23 is missing

  const std::optional<std::string> svg = SweepMapSvg(sweep, results);
  ASSERT_TRUE(svg.has_value());
  EXPECT_EQ(*svg, RenderGridMapSvg(*map));
  EXPECT_THAT(*svg, HasSubstr(">1/4</text>"));
  EXPECT_THAT(*svg, HasSubstr(">3/3</text>"));
}

TEST(SweepMapTest, ASweepOverOneAxisHasNoMap) {
  LoadedSweep sweep = Sweep(3);
  AddListAxis(sweep.spec, "vehicle.mass_kg", {0.5, 0.6});
  EXPECT_FALSE(SweepPassMap(sweep, {Row(0, true)}).has_value());
  EXPECT_FALSE(SweepMapSvg(sweep, {Row(0, true)}).has_value());
}

}  // namespace
}  // namespace hilrig::host
