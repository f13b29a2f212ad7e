// The merged files' text: CSV quoting, envelope columns across scenarios, and the command that
// runs one case alone.
#include "host/sweep/sweep_merge.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/hover_sweep.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

LoadedSweep HoverSweep(const std::string& name) {
  const std::filesystem::path dir = HoverSweepFolder(name, 0.05, 2);
  auto sweep = LoadSweep((dir / "sweep.textproto").string());
  EXPECT_TRUE(sweep.ok()) << sweep.error().message;
  return sweep.ok() ? std::move(sweep).value() : LoadedSweep{};
}

// A row of the hover sweep: case `index`, its seed and mass.
proto::SweepCaseResult HoverRow(std::uint64_t index, std::uint64_t seed, double mass_kg,
                                proto::SweepCaseResult::Outcome outcome) {
  proto::SweepCaseResult row;
  row.set_index(index);
  row.set_scenario("hover_sweep");
  row.set_seed(seed);
  row.add_value(mass_kg);
  row.set_outcome(outcome);
  return row;
}

TEST(SweepMergeTest, RunsCsvHasARowPerCaseWithItsEnvelopesAndQuotedDetail) {
  const LoadedSweep sweep = HoverSweep("sweep_merge_csv");
  std::map<std::uint64_t, proto::SweepCaseResult> rows;
  proto::SweepCaseResult& passed = rows[0] = HoverRow(0, 1, 0.5, proto::SweepCaseResult::PASSED);
  auto* envelope = passed.add_envelope();
  envelope->set_name("altitude");
  envelope->set_met(true);
  envelope->set_worst(0.01);
  envelope->set_margin(0.04);
  passed.set_real_time_factor(900);
  passed.set_wall_s(0.002);
  proto::SweepCaseResult& invalid = rows[3] = HoverRow(3, 2, 0.6, proto::SweepCaseResult::INVALID);
  invalid.set_detail("vehicle.mass_kg: \"-1\", not above 0");
  EXPECT_EQ(RunsCsv(sweep, rows),
            "case,scenario,seed,vehicle.mass_kg,outcome,altitude.met,altitude.worst,"
            "altitude.margin,detail,real_time_factor,wall_s\n"
            "0,hover_sweep,1,0.5,passed,1,0.01,0.04,,900,0.002\n"
            "3,hover_sweep,2,0.6,invalid,,,,\"vehicle.mass_kg: \"\"-1\"\", not above 0\",0,0\n");
}

TEST(SweepMergeTest, TheReproducingCommandRunsTheCaseAlone) {
  const LoadedSweep sweep = HoverSweep("sweep_merge_command");
  const proto::SweepCaseResult row = HoverRow(12, 7, 0.1 + 0.2, proto::SweepCaseResult::FAILED);
  const std::string command = ReproduceCommand(sweep, row, "/opt/hil rig/hilrig", "/out/runs");
  EXPECT_EQ(command, "'/opt/hil rig/hilrig' run " + sweep.scenarios[0].path +
                         " --seed 7 --set vehicle.mass_kg=0.30000000000000004 --no-reference"
                         " --out /out/runs/case-0000012");
}

}  // namespace
}  // namespace hilrig::host
