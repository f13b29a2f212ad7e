// The merged files' text: CSV quoting, envelope columns across scenarios, and the command that
// runs one case alone.
#include "host/sweep/sweep_merge.h"

#include <gmock/gmock.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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
  // The sweep's own sets come first, as the case applied them.
  LoadedSweep with_sets = sweep;
  ASSERT_TRUE(AddSweepSets(with_sets, {{"models.vio.latency_s", 0.05}}).ok());
  EXPECT_THAT(ReproduceCommand(with_sets, row, "hilrig", "/out/runs"),
              ::testing::HasSubstr(
                  " --set models.vio.latency_s=0.05,vehicle.mass_kg=0.30000000000000004 "));
}

std::string JsonLine(const proto::SweepCaseResult& row) {
  std::string json;
  (void)google::protobuf::util::MessageToJsonString(row, &json);
  return json + "\n";
}

// A passed row of hover case `index` (seed, mass as the sweep makes them), its envelope met.
proto::SweepCaseResult PassedHoverRow(std::uint64_t index) {
  const std::uint64_t seed = index % 2 + 1;
  proto::SweepCaseResult row =
      HoverRow(index, seed, index < 2 ? 0.5 : 0.6, proto::SweepCaseResult::PASSED);
  auto* envelope = row.add_envelope();
  envelope->set_name("altitude");
  envelope->set_met(true);
  return row;
}

// A sweep folder whose shard holds `lines`.
std::filesystem::path ShardFolder(const std::string& name, const std::string& lines) {
  const std::filesystem::path out = FreshTestDir(name);
  std::filesystem::create_directories(out / "shards");
  std::ofstream(out / "shards" / "shard-0001-of-0001.jsonl") << lines;
  return out;
}

TEST(SweepMergeTest, EveryMatchingRowCountsAndTheSweepPasses) {
  const LoadedSweep sweep = HoverSweep("sweep_merge_all");
  std::string lines;
  for (std::uint64_t index = 0; index < 4; ++index) lines += JsonLine(PassedHoverRow(index));
  auto merged = MergeSweep(sweep, ShardFolder("sweep_merge_all_out", lines).string(), "hilrig");
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  EXPECT_EQ(merged.value().finished, 4u);
  EXPECT_TRUE(merged.value().summary.complete());
  EXPECT_TRUE(merged.value().criteria_met);
  EXPECT_TRUE(merged.value().summary.passed());
}

// A sweep over two axes gets its pass map beside its page, and drawn in it; one over one axis
// gets no map.svg.
TEST(SweepMergeTest, ASweepOverTwoAxesWritesItsMapBesideThePage) {
  LoadedSweep sweep = HoverSweep("sweep_merge_map");
  proto::Axis* bound = sweep.spec.add_axis();
  bound->set_path("envelopes[0].upper");
  bound->mutable_list()->add_value(0.05);
  bound->mutable_list()->add_value(1);
  // 2 masses x 2 bounds x 2 seeds: case = mass * 4 + bound * 2 + seed - 1. All pass.
  std::string lines;
  for (std::uint64_t index = 0; index < 8; ++index) {
    proto::SweepCaseResult row = PassedHoverRow(0);
    row.set_index(index);
    row.set_seed(index % 2 + 1);
    row.set_value(0, index < 4 ? 0.5 : 0.6);
    row.add_value(index % 4 < 2 ? 0.05 : 1);
    lines += JsonLine(row);
  }
  const auto out = ShardFolder("sweep_merge_map_out", lines);
  auto merged = MergeSweep(sweep, out.string(), "hilrig");
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  ASSERT_EQ(merged.value().finished, 8u) << ::testing::PrintToString(merged.value().problems);
  const std::string map = ReadFile(out / "map.svg");
  EXPECT_EQ(map.rfind("<?xml", 0), 0u);
  EXPECT_THAT(map, HasSubstr(">2/2</text>"));
  EXPECT_THAT(map, HasSubstr(">vehicle.mass_kg</text>"));
  const std::string page = ReadFile(out / "index.html");
  EXPECT_THAT(page, HasSubstr("<h2>Pass map</h2>"));
  EXPECT_THAT(page, HasSubstr("<a href=\"map.svg\">map.svg</a>"));

  const LoadedSweep one_axis = HoverSweep("sweep_merge_no_map");
  std::string one_axis_lines;
  for (std::uint64_t index = 0; index < 4; ++index)
    one_axis_lines += JsonLine(PassedHoverRow(index));
  const auto one_axis_out = ShardFolder("sweep_merge_no_map_out", one_axis_lines);
  ASSERT_TRUE(MergeSweep(one_axis, one_axis_out.string(), "hilrig").ok());
  EXPECT_TRUE(std::filesystem::exists(one_axis_out / "index.html"));
  EXPECT_FALSE(std::filesystem::exists(one_axis_out / "map.svg"));
}

// Rows that do not match their case as the sweep spec makes it stand for no case: a forged
// scenario, seed or value, an outcome its envelopes belie, a case the sweep does not have, an
// empty object. The sweep is then incomplete, and never passes.
TEST(SweepMergeTest, ForgedAndMismatchedRowsAreRefusedAndTheSweepDoesNotPass) {
  const LoadedSweep sweep = HoverSweep("sweep_merge_forged");
  proto::SweepCaseResult wrong_scenario = PassedHoverRow(0);
  wrong_scenario.set_scenario("other");
  proto::SweepCaseResult wrong_seed = PassedHoverRow(1);
  wrong_seed.set_seed(7);
  proto::SweepCaseResult wrong_value = PassedHoverRow(2);
  wrong_value.set_value(0, 0.5);
  proto::SweepCaseResult belied = PassedHoverRow(3);
  belied.mutable_envelope(0)->set_met(false);
  proto::SweepCaseResult beyond = PassedHoverRow(3);
  beyond.set_index(4);
  const std::string lines = JsonLine(wrong_scenario) + JsonLine(wrong_seed) +
                            JsonLine(wrong_value) + JsonLine(belied) + JsonLine(beyond) + "{}\n";
  const auto out = ShardFolder("sweep_merge_forged_out", lines);
  auto merged = MergeSweep(sweep, out.string(), "hilrig");
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  EXPECT_EQ(merged.value().finished, 0u);
  EXPECT_EQ(merged.value().bad_lines, 6u);
  EXPECT_FALSE(merged.value().criteria_met);
  EXPECT_FALSE(merged.value().summary.passed());
  EXPECT_FALSE(merged.value().summary.complete());
  EXPECT_EQ(merged.value().summary.rows_refused(), 6u);
  const auto& problems = merged.value().problems;
  ASSERT_EQ(problems.size(), 6u);
  EXPECT_THAT(problems[0], HasSubstr(":1: case 0 is not of scenario hover_sweep"));
  EXPECT_THAT(problems[1], HasSubstr(":2: case 1 has seed 7, the sweep's 2"));
  EXPECT_THAT(problems[2], HasSubstr(":3: case 2 has other axis values than the sweep's"));
  EXPECT_THAT(problems[3], HasSubstr(":4: case 3 says passed without every envelope met"));
  EXPECT_THAT(problems[4], HasSubstr(":5: case 4 is not one of the sweep's 4 cases"));
  EXPECT_THAT(problems[5], HasSubstr(":6: case 0 is not of scenario hover_sweep"));
  // runs.csv has no row for a refused line: its columns stay the header's.
  EXPECT_EQ(ReadFile(out / "runs.csv").find("\n0,"), std::string::npos);
}

// A case's detail (a stop reason may quote a spec's path) is data in failing.txt: a line break in
// it does not start a line that `bash failing.txt` would run.
TEST(SweepMergeTest, FailingTxtRunsNothingButTheCasesCommands) {
  const LoadedSweep sweep = HoverSweep("sweep_merge_inject");
  proto::SweepCaseResult row = HoverRow(1, 2, 0.5, proto::SweepCaseResult::STOPPED);
  row.set_detail("dut failed: x\ntouch /tmp/hilrig_injected\n\x1b[2J");
  const auto out = ShardFolder("sweep_merge_inject_out", JsonLine(row));
  auto merged = MergeSweep(sweep, out.string(), "/opt/hilrig");
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  const std::string failing = ReadFile(out / "failing.txt");
  EXPECT_THAT(
      failing,
      HasSubstr("# case 1 stopped: dut failed: x\\ntouch /tmp/hilrig_injected\\n\\x1b[2J\n"));
  std::istringstream lines(failing);
  std::string line;
  int commands = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("#", 0) == 0) continue;
    EXPECT_EQ(line.rfind("/opt/hilrig run ", 0), 0u) << line;
    ++commands;
  }
  EXPECT_EQ(commands, 1);
}

}  // namespace
}  // namespace hilrig::host
