// `hilrig sweep` end to end on a small hover scene: the files a sweep writes, the same results
// whatever the shard count or split, the exit codes of met and failed criteria, a failing case's
// command that runs it alone, and a sweep stopped with Ctrl-C that keeps and merges what finished.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/cli_runner.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/hover_sweep.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// runs.csv without its last two columns, which time the machine rather than describe the case.
std::string RunsWithoutTiming(const fs::path& out) {
  std::istringstream csv(ReadFile(out / "runs.csv"));
  std::string line, kept;
  while (std::getline(csv, line)) {
    line.erase(line.rfind(','));
    line.erase(line.rfind(','));
    kept += line + "\n";
  }
  return kept;
}

TEST(CliSweepTest, WritesTheResultsAndPassesWhenTheCriteriaAreMet) {
  const fs::path dir = HoverSweepFolder("cli_sweep_pass", 0.05, 4);
  const CliResult result = Cli({"sweep", (dir / "sweep.textproto").string(), "--out",
                                (dir / "out").string(), "--jobs", "2"});
  EXPECT_EQ(result.exit_code, 0) << result.err << result.out;
  EXPECT_THAT(result.err, HasSubstr("hover_mass: 8 cases in 2 shards"));
  EXPECT_THAT(result.err, HasSubstr("8/8 cases, 0 not passed"));
  EXPECT_THAT(result.out, HasSubstr("PASS  criterion[0]  hover_sweep / altitude"));
  EXPECT_THAT(result.out, HasSubstr("hover_mass: PASS"));
  const std::string runs = ReadFile(dir / "out" / "runs.csv");
  EXPECT_THAT(runs, HasSubstr("case,scenario,seed,vehicle.mass_kg,outcome,altitude.met,"));
  EXPECT_THAT(runs, HasSubstr("\n0,hover_sweep,1,0.5,passed,1,"));
  EXPECT_THAT(runs, HasSubstr("\n7,hover_sweep,4,0.6,passed,1,"));
  EXPECT_THAT(ReadFile(dir / "out" / "summary.json"), HasSubstr("\"met\": \"8\""));
  EXPECT_EQ(ReadFile(dir / "out" / "failing.txt"), "");
  EXPECT_THAT(ReadFile(dir / "out" / "index.html"),
              HasSubstr("<h1>Sweep hover_mass <span class=\"badge pass\">PASS</span></h1>"));
  EXPECT_FALSE(fs::exists(dir / "out" / "runs"));  // nothing failed, no run kept its files
}

TEST(CliSweepTest, TheResultsAreTheSameWhateverTheShardsAndTheSplit) {
  const fs::path dir = HoverSweepFolder("cli_sweep_shards", 0.05, 5);
  const std::string sweep = (dir / "sweep.textproto").string();
  ASSERT_EQ(Cli({"sweep", sweep, "--out", (dir / "one").string(), "--jobs", "1"}).exit_code, 0);
  ASSERT_EQ(Cli({"sweep", sweep, "--out", (dir / "three").string(), "--jobs", "3"}).exit_code, 0);
  // A cluster's way: each shard on its own, then the merge.
  const std::string split = (dir / "split").string();
  for (const char* shard : {"1/2", "2/2"}) {
    const CliResult ran = Cli({"sweep", sweep, "--out", split, "--shard", shard});
    ASSERT_EQ(ran.exit_code, 0) << ran.err;
    EXPECT_EQ(ran.out, "");
  }
  // The merge needs the sweep beside the shards, which a local sweep writes; a cluster job
  // script copies it there the same way.
  fs::copy_file(dir / "one" / "sweep.textproto", dir / "split" / "sweep.textproto");
  const CliResult merged = Cli({"sweep", "--merge", split});
  ASSERT_EQ(merged.exit_code, 0) << merged.err << merged.out;
  const std::string summary = ReadFile(dir / "one" / "summary.json");
  EXPECT_EQ(ReadFile(dir / "three" / "summary.json"), summary);
  EXPECT_EQ(ReadFile(dir / "split" / "summary.json"), summary);
  const std::string runs = RunsWithoutTiming(dir / "one");
  EXPECT_EQ(RunsWithoutTiming(dir / "three"), runs);
  EXPECT_EQ(RunsWithoutTiming(dir / "split"), runs);
  const std::string page = ReadFile(dir / "one" / "index.html");
  EXPECT_THAT(page, HasSubstr("<svg"));
  EXPECT_EQ(ReadFile(dir / "three" / "index.html"), page);
  EXPECT_EQ(ReadFile(dir / "split" / "index.html"), page);
}

// A failing case's command names its scenario by the same absolute path whether the sweep merged
// here or `--merge DIR` ran elsewhere, however the sweep file wrote the path.
TEST(CliSweepTest, AFailingCasesCommandIsTheSameFromALocalSweepAndAMerge) {
  const fs::path dir = HoverSweepFolder("cli_sweep_paths", 1e-6, 2);
  fs::create_directories(dir / "sub");
  std::string text = ReadFile(dir / "sweep.textproto");
  text.replace(text.find("\"hover.textproto\""), 17, "\"sub/../hover.textproto\"");
  std::ofstream(dir / "sweep.textproto", std::ios::trunc) << text;
  const fs::path local = dir / "local";
  ASSERT_EQ(
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", local.string(), "--jobs", "2"})
          .exit_code,
      1);
  const std::string failing = ReadFile(local / "failing.txt");
  std::string command = "run ";  // built by appends: GCC 12 warns falsely on "x" + string
  command += (dir / "hover.textproto").string();
  command += " --seed";
  EXPECT_THAT(failing, HasSubstr(command));
  const std::string page = ReadFile(local / "index.html");
  ASSERT_EQ(Cli({"sweep", "--merge", local.string()}).exit_code, 1);
  EXPECT_EQ(ReadFile(local / "failing.txt"), failing);
  EXPECT_EQ(ReadFile(local / "index.html"), page);
}

TEST(CliSweepTest, FailsWhenTheCriteriaAreNotMetAndNamesACommandPerFailingCase) {
  const fs::path dir = HoverSweepFolder("cli_sweep_fail", 1e-6, 2);
  const fs::path out = dir / "out";
  const CliResult result =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(), "--jobs", "2"});
  EXPECT_EQ(result.exit_code, 1) << result.err << result.out;
  EXPECT_THAT(result.out, HasSubstr("FAIL  criterion[0]  hover_sweep / altitude"));
  EXPECT_THAT(result.out, HasSubstr("hover_mass: FAIL"));
  const std::string failing = ReadFile(out / "failing.txt");
  EXPECT_THAT(failing, HasSubstr("# case 3 failed\n"));
  // A failing case keeps its files, from a run identical to the one that failed, and the sweep's
  // page links to the page of its folder.
  EXPECT_TRUE(fs::exists(out / "runs" / "case-0000003" / "trace.csv"));
  EXPECT_THAT(ReadFile(out / "index.html"),
              HasSubstr("<a href=\"runs/case-0000003/index.html\">3</a>"));
  EXPECT_THAT(ReadFile(out / "runs" / "case-0000003" / "index.html"),
              HasSubstr("<span class=\"badge fail\">FAIL</span>"));
  // The command of case 3 (seed 2, mass 0.6) runs it alone and fails the same way.
  const std::size_t at = failing.find("# case 3 failed\n");
  const std::size_t start = failing.find('\n', at) + 1;
  std::string command = failing.substr(start, failing.find('\n', start) - start);
  EXPECT_THAT(command, HasSubstr(" --seed 2 --set vehicle.mass_kg=0.6 --no-reference --out "));
  command.replace(command.rfind("case-0000003"), 12, "again");
  ASSERT_EQ(command.rfind(::hilrig::test_support::BinDir(), 0), 0u) << command;
  const ProcessResult again =
      RunHilrig(command.substr(::hilrig::test_support::BinDir().size() + 8), dir / "again.err");
  EXPECT_EQ(again.exit_code, 1) << again.err;
  EXPECT_EQ(ReadFile(out / "runs" / "again" / "trace.csv"),
            ReadFile(out / "runs" / "case-0000003" / "trace.csv"));
}

// `--set` changes every case for one sweep: the folder's sweep keeps it, so a merge and each
// failing case's command carry it; a path an axis sweeps is refused before anything runs.
TEST(CliSweepTest, SetChangesEveryCaseAndTravelsWithTheSweep) {
  const fs::path dir = HoverSweepFolder("cli_sweep_set", 1e-6, 1);
  const fs::path out = dir / "out";
  const CliResult result = Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(),
                                "--jobs", "1", "--set", "models.vio.latency_s=0.05"});
  EXPECT_EQ(result.exit_code, 1) << result.err << result.out;
  EXPECT_THAT(ReadFile(out / "sweep.textproto"),
              HasSubstr("set {\n  path: \"models.vio.latency_s\"\n  value: 0.05\n}"));
  EXPECT_THAT(ReadFile(out / "failing.txt"),
              HasSubstr(" --seed 1 --set models.vio.latency_s=0.05,vehicle.mass_kg=0.5 "));
  const CliResult swept = Cli({"sweep", (dir / "sweep.textproto").string(), "--out",
                               (dir / "out2").string(), "--set", "vehicle.mass_kg=0.7"});
  EXPECT_EQ(swept.exit_code, 2);
  EXPECT_THAT(swept.err,
              HasSubstr("--set vehicle.mass_kg: \"vehicle.mass_kg\" is swept by an axis"));
  EXPECT_FALSE(fs::exists(dir / "out2" / "runs.csv"));
}

TEST(CliSweepTest, ABadSweepOrUsageIsRefusedWithExitTwo) {
  const fs::path dir =
      HoverSweepFolder("cli_sweep_bad", 0.05, 2, "criterion { envelope: \"nope\" }");
  const CliResult bad =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("sweep.textproto:5:1: criterion[0]: set min_pass_rate"));
  EXPECT_THAT(bad.err, HasSubstr("criterion[0].envelope: no envelope \"nope\""));
  EXPECT_FALSE(fs::exists(dir / "out"));
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"sweep"},
                                             {"sweep", (dir / "sweep.textproto").string()},
                                             {"sweep", "a", "--out", "o", "--jobs", "0"},
                                             {"sweep", "a", "--out", "o", "--shard", "3/2"},
                                             {"sweep", "--merge", "o", "--jobs", "2"}}) {
    const CliResult usage = Cli(args);
    EXPECT_EQ(usage.exit_code, 2) << args.size();
    EXPECT_THAT(usage.err, HasSubstr("see `hilrig help sweep`"));
  }
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"sweep", "a", "--out", "o", "--partition", "short"},
           {"sweep", "a", "--out", "o", "--wait"},
           {"sweep", "a", "--out", "o", "--slurm", "--shard", "1/2"},
           {"sweep", "a", "--out", "o", "--slurm", "--max-parallel", "0"},
           {"sweep", "a", "--out", "o", "--slurm", "--partition", "a b"}}) {
    const CliResult slurm = Cli(args);
    EXPECT_EQ(slurm.exit_code, 2) << args.back();
    EXPECT_THAT(slurm.err, HasSubstr("see `hilrig help sweep`"));
  }
  // #SBATCH --output cannot take a path with a space: refused before anything is submitted.
  const fs::path good = HoverSweepFolder("cli_sweep_space", 0.05, 1);
  const fs::path spaced = good / "out with space";
  const CliResult space =
      Cli({"sweep", (good / "sweep.textproto").string(), "--out", spaced.string(), "--slurm"});
  EXPECT_EQ(space.exit_code, 2);
  EXPECT_THAT(space.err, HasSubstr("has a space or a %"));
  EXPECT_FALSE(fs::exists(spaced / "slurm"));
  const CliResult no_sweep = Cli({"sweep", "--merge", (dir / "nothing").string()});
  EXPECT_EQ(no_sweep.exit_code, 2);
  EXPECT_THAT(no_sweep.err, HasSubstr("nothing/sweep.textproto"));
}

// Ctrl-C: the shards stop, what finished is merged, and the sweep says it is incomplete. (One
// SIGINT, to hilrig alone: without --foreground, timeout signals its process group as well, and a
// second signal ends hilrig at once.)
TEST(CliSweepTest, AStoppedSweepKeepsAndMergesWhatFinished) {
  // 2000 cases of 10 s each: far more than finish in the 1.5 s before the stop, and each short
  // enough that some do, in the sanitizer build on a busy machine too.
  const fs::path dir =
      HoverSweepFolder("cli_sweep_stop", 0.05, 1000, "criterion { min_pass_rate: 0.5 }", 10);
  const fs::path out = dir / "out";
  const std::string command =
      "timeout --foreground --preserve-status -s INT 1.5 " + ::hilrig::test_support::BinDir() +
      "/hilrig sweep " + (dir / "sweep.textproto").string() + " --out " + out.string() +
      " --jobs 2 >" + (dir / "stop.out").string() + " 2>" + (dir / "stop.err").string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << ReadFile(dir / "stop.err");
  const std::string printed = ReadFile(dir / "stop.out");
  EXPECT_THAT(printed, HasSubstr("INCOMPLETE (stopped)"));
  std::istringstream runs(ReadFile(out / "runs.csv"));
  std::string line;
  int rows = -1;  // the header
  while (std::getline(runs, line)) ++rows;
  EXPECT_GT(rows, 0);
  EXPECT_LT(rows, 2000);
  EXPECT_THAT(printed, HasSubstr("hover_mass: " + std::to_string(rows) + " of 2000 cases"));
  const std::string page = ReadFile(out / "index.html");
  EXPECT_THAT(page, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(page, HasSubstr(std::to_string(rows) + " of 2000 cases finished"));
  // Every finished case passed, and still the summary does not say the sweep did.
  const std::string summary = ReadFile(out / "summary.json");
  EXPECT_THAT(summary, HasSubstr("\"passed\": false"));
  EXPECT_THAT(summary, HasSubstr("\"complete\": false"));
}

}  // namespace
}  // namespace hilrig::host
