// `hilrig compare` as a CI job calls it between two builds' results: a grasp controller weakened
// through the spec (four times the damping of its admittance, so the force builds four times
// slower) is flagged in a run and in a sweep, an unchanged one is not, the sweep cases whose
// verdict flipped are named, and folders it cannot compare are refused with exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <map>
#include <vector>

#include "host/sweep/sweep_merge.h"
#include "host/sweep/sweep_statistics.h"
#include "proto/compare.pb.h"
#include "tests/support/cli_runner.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/hover_sweep.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kBalloon =
    ::hilrig::test_support::SourceDir() + "/scenarios/balloon_grasp.textproto";
// The shipped damping is 65 N s/rad; 4x makes the grasp force miss its band after 6 s.
const std::string kWeakGrasp = "grasp_controller.damping=260";

CliResult RunBalloon(const fs::path& out, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"run", kBalloon, "--no-reference", "--out", out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return Cli(args);
}

TEST(CliCompareTest, AWeakenedGraspControllerIsARegressionAnUnchangedOneIsNot) {
  const fs::path dir = FreshTestDir("cli_compare");
  ASSERT_EQ(RunBalloon(dir / "base").exit_code, 0);
  ASSERT_EQ(RunBalloon(dir / "same").exit_code, 0);
  ASSERT_EQ(RunBalloon(dir / "weak", {"--set", kWeakGrasp}).exit_code, 1);

  const CliResult same = Cli({"compare", (dir / "base").string(), (dir / "same").string()});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_THAT(same.out, HasSubstr("3400 rows compared (base 3400, candidate 3400), 50 signals, "
                                  "0 differ"));
  EXPECT_THAT(same.out, HasSubstr("candidate is not worse than the base"));
  EXPECT_THAT(same.out, Not(HasSubstr("WORSE")));

  const std::string json = (dir / "compare.json").string();
  const CliResult weak =
      Cli({"compare", (dir / "base").string(), (dir / "weak").string(), "--out", json});
  EXPECT_EQ(weak.exit_code, 1) << weak.out << weak.err;
  EXPECT_THAT(weak.out, HasSubstr("completed, PASS -> FAIL"));
  EXPECT_THAT(weak.out, HasSubstr("candidate is WORSE than the base"));
  EXPECT_THAT(weak.out, HasSubstr("envelope grasp_force: met in the base, not in the candidate"));
  // The servo is where the traces part, before the grasp force follows.
  EXPECT_THAT(weak.out, HasSubstr("servo_command_rad           diverges at 1.6"));
  EXPECT_THAT(ReadFile(json), HasSubstr("\"worse\": true"));
}

// Two folder runs as ./scripts/run writes them, compared scene by scene: the same scenes at the
// same seed are not worse; a scene weakened in the candidate is, by name; a scene one side has
// alone is listed and not graded.
TEST(CliCompareTest, ComparesTwoFolderRunsSceneByScene) {
  const fs::path dir = FreshTestDir("cli_compare_folders");
  fs::create_directories(dir / "scenes");
  fs::copy_file(kBalloon, dir / "scenes" / "balloon_grasp.textproto");
  std::ofstream(dir / "scenes" / "hover.textproto")
      << "name: \"hover\"\nvehicle { initial_position_m { z: 1 } }\n"
         "simulation { duration_s: 1 }\n"
         "envelopes { name: \"altitude\" signal: ALTITUDE_ERROR_M upper: 0.05 }\n";
  const auto run_folder = [&](const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"run", (dir / "scenes").string() + "/", "--no-reference",
                                     "--out", (dir / out).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return Cli(args);
  };
  ASSERT_EQ(run_folder("base", {}).exit_code, 0);
  ASSERT_EQ(run_folder("same", {}).exit_code, 0);
  ASSERT_EQ(run_folder("weak", {"--set", kWeakGrasp}).exit_code, 1);
  // A scene that did not run (a spec that no longer loads) leaves no report in its folder run.
  fs::remove_all(dir / "weak" / "hover");

  const CliResult same = Cli({"compare", (dir / "base").string(), (dir / "same").string()});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_THAT(same.out, HasSubstr("folder run: 2 scenes in both; only in the base: none; only in "
                                  "the candidate: none"));
  EXPECT_THAT(same.out, HasSubstr("balloon_grasp: not worse"));
  EXPECT_THAT(same.out, HasSubstr("hover: not worse"));

  // The weakened folder run has no hover: listed, not graded.
  const CliResult weak = Cli({"compare", (dir / "base").string(), (dir / "weak").string()});
  EXPECT_EQ(weak.exit_code, 1) << weak.out << weak.err;
  EXPECT_THAT(weak.out, HasSubstr("1 scenes in both; only in the base: hover;"));
  EXPECT_THAT(weak.out, HasSubstr("balloon_grasp: WORSE"));
  EXPECT_THAT(weak.out, HasSubstr("balloon_grasp: envelope grasp_force: met in the base, not in "
                                  "the candidate"));
  // A folder run against a single run is refused by kind.
  const CliResult mixed =
      Cli({"compare", (dir / "base").string(), (dir / "base" / "hover").string()});
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_THAT(mixed.err, HasSubstr("different kinds of result (a folder run, a run)"));
}

void WriteSweep(const fs::path& dir, const std::string& name, const std::string& grasp) {
  std::ofstream(dir / (name + ".textproto")) << ReadFile(kBalloon) << grasp << "\n";
  std::ofstream(dir / (name + "_sweep.textproto"))
      << "name: \"balloon_" << name << "\"\nscenario: \"" << name
      << ".textproto\"\nseeds { count: 6 }\n"
         "criterion { envelope: \"grasp_force\" min_pass_rate: 0.5 }\n";
}

CliResult Sweep(const fs::path& dir, const std::string& name, const std::string& out) {
  return Cli({"sweep", (dir / (name + "_sweep.textproto")).string(), "--out", (dir / out).string(),
              "--jobs", "2"});
}

TEST(CliCompareTest, AWeakenedGraspControllerFailsASweepsComparison) {
  const fs::path dir = FreshTestDir("cli_compare");
  WriteSweep(dir, "base", "");
  WriteSweep(dir, "weak", "grasp_controller { damping: 260 }");
  ASSERT_EQ(Sweep(dir, "base", "base_out").exit_code, 0);
  ASSERT_EQ(Sweep(dir, "base", "again_out").exit_code, 0);
  ASSERT_EQ(Sweep(dir, "weak", "weak_out").exit_code, 1);

  const CliResult same =
      Cli({"compare", (dir / "base_out").string(), (dir / "again_out").string()});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_THAT(same.out, HasSubstr("balloon_grasp/grasp_force           pass 100 % (6/6)  p 1"));
  EXPECT_THAT(same.out, HasSubstr("cases: 6 in both sweeps, matched by scenario, seed and axis "
                                  "values; no verdict changed"));
  const CliResult weak = Cli({"compare", (dir / "base_out").string(), (dir / "weak_out").string()});
  EXPECT_EQ(weak.exit_code, 1) << weak.out << weak.err;
  EXPECT_THAT(weak.out, HasSubstr("pass 100 % (6/6) -> 0 % (0/6)  p 0.00108"));
  EXPECT_THAT(weak.out, HasSubstr("; 6 now failing, 0 now passing,"));
  EXPECT_THAT(weak.out, HasSubstr("    case 5: balloon_grasp, seed 6: passed -> failed\n"));
  EXPECT_THAT(weak.out, HasSubstr("balloon_grasp/grasp_force: the pass rate fell significantly"));
  EXPECT_THAT(weak.out, HasSubstr("criterion[0] (balloon_grasp/grasp_force): met in the base"));
}

// A hover sweep's folder (2 masses x 2 seeds) as the merge writes it, its runs.csv and
// summary.json made by the sweep's own writers from cases that ended with `outcomes`.
void WriteHoverSweepFolder(const fs::path& out, const LoadedSweep& sweep,
                           const std::vector<proto::SweepCaseResult::Outcome>& outcomes) {
  std::map<std::uint64_t, proto::SweepCaseResult> rows;
  std::vector<proto::SweepCaseResult> results;
  for (std::uint64_t index = 0; index < outcomes.size(); ++index) {
    proto::SweepCaseResult& row = rows[index];
    row.set_index(index);
    row.set_scenario("hover_sweep");
    row.set_seed(index % 2 + 1);
    row.add_value(index < 2 ? 0.5 : 0.6);
    row.set_outcome(outcomes[index]);
    auto* envelope = row.add_envelope();
    envelope->set_name("altitude");
    envelope->set_met(outcomes[index] == proto::SweepCaseResult::PASSED);
    envelope->set_worst(envelope->met() ? 0.01 : 0.09);
    envelope->set_margin(envelope->met() ? 0.04 : -0.04);
    results.push_back(row);
  }
  proto::SweepSummary summary = SummariseSweep(sweep, results);
  summary.set_sweep_cases(outcomes.size());
  summary.set_complete(true);
  fs::create_directories(out);
  std::ofstream(out / "runs.csv") << RunsCsv(sweep, rows);
  std::ofstream(out / "summary.json") << SummaryJson(summary).value();
}

// One case fails that passed and one passes that failed: the pass rate holds, so the verdict is
// "not worse" and exit 0, and the output names both cases with their seed and mass. A damaged or
// missing runs.csv cannot be compared: exit 2, naming the file and the line.
TEST(CliCompareTest, NamesTheSweepCasesWhoseVerdictFlipped) {
  const fs::path dir = HoverSweepFolder("cli_compare_flips", 0.05, 2);
  auto sweep = LoadSweep((dir / "sweep.textproto").string());
  ASSERT_TRUE(sweep.ok()) << sweep.error().message;
  constexpr auto kPassed = proto::SweepCaseResult::PASSED;
  constexpr auto kFailed = proto::SweepCaseResult::FAILED;
  WriteHoverSweepFolder(dir / "base", sweep.value(), {kPassed, kPassed, kFailed, kPassed});
  WriteHoverSweepFolder(dir / "candidate", sweep.value(), {kFailed, kPassed, kPassed, kPassed});

  const std::string json = (dir / "compare.json").string();
  const CliResult flipped =
      Cli({"compare", (dir / "base").string(), (dir / "candidate").string(), "--out", json});
  EXPECT_EQ(flipped.exit_code, 0) << flipped.out << flipped.err;
  EXPECT_THAT(flipped.out, HasSubstr("cases: 4 in both sweeps, matched by scenario, seed and axis "
                                     "values; 1 now failing, 1 now passing, 0 only in the base, 0 "
                                     "only in the candidate (listed, not graded"));
  EXPECT_THAT(flipped.out, HasSubstr("  now failing (passed in the base): 1\n"
                                     "    case 0: hover_sweep, seed 1, vehicle.mass_kg=0.5: "
                                     "passed -> failed\n"));
  EXPECT_THAT(flipped.out, HasSubstr("  now passing (did not pass in the base): 1\n"
                                     "    case 2: hover_sweep, seed 1, vehicle.mass_kg=0.6: "
                                     "failed -> passed\n"));
  EXPECT_THAT(flipped.out, HasSubstr("candidate is not worse than the base"));
  EXPECT_THAT(ReadFile(json), HasSubstr("\"now_failing_count\": \"1\""));

  // The candidate's runs.csv with an outcome mistyped on its third line.
  fs::copy(dir / "candidate", dir / "damaged", fs::copy_options::recursive);
  std::string runs = ReadFile(dir / "damaged" / "runs.csv");
  const std::size_t third = runs.find('\n', runs.find('\n') + 1) + 1;
  runs.replace(runs.find("passed", third), 6, "passd");
  std::ofstream(dir / "damaged" / "runs.csv", std::ios::trunc) << runs;
  const CliResult damaged = Cli({"compare", (dir / "base").string(), (dir / "damaged").string()});
  EXPECT_EQ(damaged.exit_code, 2) << damaged.out;
  EXPECT_THAT(damaged.err, HasSubstr((dir / "damaged" / "runs.csv").string() +
                                     ":3: outcome \"passd\" is none of passed, failed"));
  fs::remove(dir / "damaged" / "runs.csv");
  const CliResult missing = Cli({"compare", (dir / "damaged").string(), (dir / "base").string()});
  EXPECT_EQ(missing.exit_code, 2) << missing.out;
  EXPECT_THAT(missing.err, HasSubstr("cannot read " + (dir / "damaged" / "runs.csv").string()));
}

TEST(CliCompareTest, RefusesWhatItCannotCompare) {
  const fs::path dir = FreshTestDir("cli_compare");
  ASSERT_EQ(RunBalloon(dir / "run").exit_code, 0);
  fs::create_directories(dir / "sweep");
  std::ofstream(dir / "sweep" / "summary.json") << "{\"sweep\": \"s\"}";
  const std::string run = (dir / "run").string();
  const CliResult mixed = Cli({"compare", run, (dir / "sweep").string()});
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_THAT(mixed.err, HasSubstr("the folders hold different kinds of result"));
  const CliResult missing = Cli({"compare", run, (dir / "nowhere").string()});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.err, HasSubstr("nowhere is not a folder"));
  const CliResult one = Cli({"compare", run});
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_THAT(one.err, HasSubstr("compare takes two folders"));
  const CliResult tolerance = Cli({"compare", run, run, "--confidence", "1.5"});
  EXPECT_EQ(tolerance.exit_code, 2);
  EXPECT_THAT(tolerance.err, HasSubstr("--confidence must be from 0 to 1, not 1.5"));
  // A damaged trace is reported, and the verdicts are still compared.
  fs::copy(run, dir / "damaged", fs::copy_options::recursive);
  ChangeByteFromEnd(dir / "damaged" / "trace.csv", 2);  // a digit of the last row, now a letter
  const CliResult damaged = Cli({"compare", run, (dir / "damaged").string()});
  EXPECT_EQ(damaged.exit_code, 0) << damaged.out;
  EXPECT_THAT(damaged.out, HasSubstr("stopped early: the candidate trace's line 3401 is not 51"));
  // A FIFO or /dev/zero in place of a trace: named, never waited on or read without end (a
  // process of its own, bounded, so a hang fails the test instead of hanging it).
  for (const char* kind : {"fifo", "zero"}) {
    const fs::path hostile = dir / kind;
    fs::copy(run, hostile, fs::copy_options::recursive);
    fs::remove(hostile / "trace.csv");
    if (std::string(kind) == "fifo") {
      ASSERT_EQ(::mkfifo((hostile / "trace.csv").c_str(), 0600), 0);
    } else {
      fs::create_symlink("/dev/zero", hostile / "trace.csv");
    }
    const ProcessResult compared =
        RunHilrig("compare " + run + " " + hostile.string() + " >" + (dir / kind).string() + ".out",
                  dir / (std::string(kind) + ".err"));
    EXPECT_EQ(compared.exit_code, 0) << compared.err;
    EXPECT_THAT(ReadFile(dir / (std::string(kind) + ".out")),
                HasSubstr(std::string(kind) == "fifo" ? "a FIFO, not a regular file"
                                                      : "a device, not a regular file"));
  }
}

}  // namespace
}  // namespace hilrig::host
