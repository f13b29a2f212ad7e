// `hilrig compare` as a CI job calls it between two builds' results: a grasp controller weakened
// through the spec (four times the damping of its admittance, so the force builds four times
// slower) is flagged in a run and in a sweep, an unchanged one is not, and folders it cannot
// compare are refused with exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "proto/compare.pb.h"
#include "tests/support/cli_runner.h"
#include "tests/support/hilrig_process.h"
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
  const CliResult weak = Cli({"compare", (dir / "base_out").string(), (dir / "weak_out").string()});
  EXPECT_EQ(weak.exit_code, 1) << weak.out << weak.err;
  EXPECT_THAT(weak.out, HasSubstr("pass 100 % (6/6) -> 0 % (0/6)  p 0.00108"));
  EXPECT_THAT(weak.out, HasSubstr("balloon_grasp/grasp_force: the pass rate fell significantly"));
  EXPECT_THAT(weak.out, HasSubstr("criterion[0] (balloon_grasp/grasp_force): met in the base"));
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
