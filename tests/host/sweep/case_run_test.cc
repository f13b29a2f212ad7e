// One case through the run pipeline: the row it makes when it passes, fails, is invalid or is
// stopped, and the files a failing case keeps.
#include "host/sweep/case_run.h"

#include <gtest/gtest.h>

#include "rig/clock.h"
#include "tests/support/hover_sweep.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

LoadedSweep Load(const fs::path& dir) {
  auto sweep = LoadSweep((dir / "sweep.textproto").string());
  EXPECT_TRUE(sweep.ok()) << sweep.error().message;
  return sweep.ok() ? std::move(sweep).value() : LoadedSweep{};
}

// Runs case `index` of the sweep in `dir`, keeping failing cases' files in DIR/runs.
std::optional<proto::SweepCaseResult> RunCaseIn(const fs::path& dir, const LoadedSweep& sweep,
                                                std::uint64_t index) {
  const rig::SteadyClock clock;
  CaseRunSetup setup;
  setup.wall_clock = &clock;
  setup.runs_dir = (dir / "runs").string();
  return RunCase(sweep, SweepCaseSpace(sweep).CaseAt(index), setup);
}

TEST(CaseRunTest, APassingCaseGivesItsEnvelopesAndKeepsNoFiles) {
  const fs::path dir = HoverSweepFolder("case_run_pass", 0.05, 2);
  const auto row = RunCaseIn(dir, Load(dir), 3);
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(row->index(), 3u);
  EXPECT_EQ(row->scenario(), "hover_sweep");
  EXPECT_EQ(row->seed(), 2u);
  ASSERT_EQ(row->value_size(), 1);
  EXPECT_EQ(row->value(0), 0.6);
  EXPECT_EQ(row->outcome(), proto::SweepCaseResult::PASSED);
  ASSERT_EQ(row->envelope_size(), 1);
  EXPECT_EQ(row->envelope(0).name(), "altitude");
  EXPECT_TRUE(row->envelope(0).met());
  EXPECT_GT(row->envelope(0).margin(), 0);
  EXPECT_GT(row->real_time_factor(), 0);
  EXPECT_FALSE(fs::exists(dir / "runs"));
}

TEST(CaseRunTest, AFailingCaseKeepsTheFilesOfItsRun) {
  const fs::path dir = HoverSweepFolder("case_run_fail", 1e-6, 1);
  const auto row = RunCaseIn(dir, Load(dir), 1);
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(row->outcome(), proto::SweepCaseResult::FAILED);
  EXPECT_FALSE(row->envelope(0).met());
  EXPECT_LT(row->envelope(0).margin(), 0);
  EXPECT_TRUE(fs::exists(dir / "runs" / "case-0000001" / "trace.csv"));
  EXPECT_TRUE(fs::exists(dir / "runs" / "case-0000001" / "report.json"));
}

TEST(CaseRunTest, AnInvalidCaseIsARowAndAStoppedOneIsNone) {
  const fs::path dir = HoverSweepFolder("case_run_invalid", 0.05, 1);
  LoadedSweep sweep = Load(dir);
  sweep.spec.mutable_axis(0)->mutable_list()->set_value(1, -1);  // a negative mass
  const rig::SteadyClock clock;
  CaseRunSetup setup;
  setup.wall_clock = &clock;
  const auto invalid = RunCase(sweep, SweepCaseSpace(sweep).CaseAt(1), setup);
  ASSERT_TRUE(invalid.has_value());
  EXPECT_EQ(invalid->outcome(), proto::SweepCaseResult::INVALID);
  EXPECT_NE(invalid->detail().find("vehicle.mass_kg"), std::string::npos) << invalid->detail();
  const std::atomic<bool> stop{true};
  setup.stop_requested = &stop;
  EXPECT_FALSE(RunCase(sweep, SweepCaseSpace(sweep).CaseAt(0), setup).has_value());
}

}  // namespace
}  // namespace hilrig::host
