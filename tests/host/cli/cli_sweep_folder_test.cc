// A sweep's folder is its own while it runs, and a sweep that cannot start leaves it as it was: a
// second sweep or a merge into a folder in use is refused by name, a refused --slurm changes
// nothing, an earlier sweep's case folders do not stand beside a new result, and a sweep killed
// outright takes its shards with it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <time.h>

#include <fstream>
#include <map>

#include "host/link/child_process.h"
#include "tests/support/cli_runner.h"
#include "tests/support/hover_sweep.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

void NapMs(int ms) {
  const timespec nap{0, ms * 1'000'000L};
  ::nanosleep(&nap, nullptr);
}

// Waits up to `ms` for `ready`; false when it never was.
template <typename Ready>
bool WaitFor(int ms, Ready ready) {
  for (int waited = 0; waited < ms; waited += 20) {
    if (ready()) return true;
    NapMs(20);
  }
  return ready();
}

// A sweep of 2000 cases of 30 s each, started as its own process into `out` and returned once both
// its shards have opened their files: it runs far longer than any test waits.
ChildProcess StartLongSweep(const fs::path& dir, const fs::path& out) {
  auto child = ChildProcess::Spawn({test_support::BinDir() + "/hilrig", "sweep",
                                    (dir / "sweep.textproto").string(), "--out", out.string(),
                                    "--jobs", "2"});
  EXPECT_TRUE(child.ok()) << child.error().message;
  EXPECT_TRUE(WaitFor(10000, [&] {
    return fs::exists(out / "shards" / "shard-0001-of-0002.jsonl") &&
           fs::exists(out / "shards" / "shard-0002-of-0002.jsonl");
  }));
  return std::move(child).value();
}

// The pids of the processes whose command line holds `text`.
std::vector<pid_t> ProcessesWith(const std::string& text) {
  std::vector<pid_t> pids;
  std::error_code error;
  for (fs::directory_iterator entry("/proc", error), end; !error && entry != end;
       entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string command = ReadFile(entry->path() / "cmdline");
    for (char& c : command) c = c == '\0' ? ' ' : c;
    if (command.find(text) != std::string::npos) pids.push_back(std::stoi(name));
  }
  return pids;
}

// Every file under `dir` (lock files aside) with its bytes.
std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().filename() == ".hilrig.lock") continue;
    files[fs::relative(entry.path(), dir).string()] = ReadFile(entry.path());
  }
  return files;
}

TEST(CliSweepFolderTest, ASecondSweepOrAMergeIntoAFolderInUseIsRefusedByName) {
  const fs::path dir =
      HoverSweepFolder("cli_sweep_busy", 0.05, 1000, "criterion { min_pass_rate: 0.5 }", 30);
  const fs::path out = dir / "out";
  ChildProcess first = StartLongSweep(dir, out);
  const CliResult second =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(), "--jobs", "1"});
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_THAT(second.err,
              HasSubstr("in use by another hilrig process: pid " + std::to_string(first.pid())));
  const CliResult merge = Cli({"sweep", "--merge", out.string()});
  EXPECT_EQ(merge.exit_code, 2) << merge.err;
  EXPECT_THAT(merge.err, HasSubstr("in use by another hilrig process"));
  // The refused sweep touched nothing: the first one's shards are still being written.
  EXPECT_TRUE(fs::exists(out / "shards" / "shard-0001-of-0002.jsonl"));
  first.Terminate(5000);
  EXPECT_THAT(ReadFile(out / "summary.json"), HasSubstr("\"passed\": false"));
}

TEST(CliSweepFolderTest, ASweepKilledOutrightLeavesNoShardRunning) {
  const fs::path dir =
      HoverSweepFolder("cli_sweep_kill", 0.05, 1000, "criterion { min_pass_rate: 0.5 }", 30);
  const fs::path out = dir / "out";
  ChildProcess sweep = StartLongSweep(dir, out);
  const std::string shard_mark = out.string() + " --shard";
  ASSERT_TRUE(WaitFor(10000, [&] { return ProcessesWith(shard_mark).size() == 2; }));
  ::kill(sweep.pid(), SIGKILL);
  sweep.Terminate(0);
  EXPECT_TRUE(WaitFor(2000, [&] { return ProcessesWith(shard_mark).empty(); }))
      << ProcessesWith(shard_mark).size() << " shards still running";
}

// A sweep's earlier results, the folder as they left it.
fs::path FolderWithAnEarlierSweep(const std::string& name) {
  const fs::path dir = HoverSweepFolder(name, 1e-6, 2);
  const fs::path out = dir / "out";
  const CliResult earlier =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(), "--jobs", "1"});
  EXPECT_EQ(earlier.exit_code, 1) << earlier.err;
  EXPECT_TRUE(fs::exists(out / "runs" / "case-0000001" / "trace.csv"));
  return dir;
}

TEST(CliSweepFolderTest, ASlurmSweepThatSbatchRefusesLeavesTheFolderAsItWas) {
  const fs::path dir = FolderWithAnEarlierSweep("cli_sweep_sbatch");
  const fs::path out = dir / "out";
  const auto before = Snapshot(out);
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "sbatch")
      << "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n";
  fs::permissions(bin / "sbatch", fs::perms::owner_all);
  const std::string path = ::getenv("PATH");
  ::setenv("PATH", (bin.string() + ":" + path).c_str(), 1);
  const CliResult refused =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(), "--slurm"});
  ::setenv("PATH", path.c_str(), 1);
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_THAT(refused.err, HasSubstr("without a job id"));
  EXPECT_EQ(Snapshot(out), before);
  EXPECT_FALSE(fs::exists(out / ".previous-sweep"));
}

TEST(CliSweepFolderTest, ASlurmSweepRefusedForItsPathChangesNothing) {
  const fs::path dir = FolderWithAnEarlierSweep("cli_sweep_slurm_space");
  const fs::path spaced = dir / "out space";
  fs::rename(dir / "out", spaced);
  const auto before = Snapshot(spaced);
  const CliResult refused =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", spaced.string(), "--slurm"});
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_THAT(refused.err, HasSubstr("has a space or a %"));
  EXPECT_EQ(Snapshot(spaced), before);
}

TEST(CliSweepFolderTest, AnEarlierSweepsCaseFoldersDoNotStandBesideANewResult) {
  const fs::path dir = FolderWithAnEarlierSweep("cli_sweep_again");
  // The same folder, now with a limit every case meets.
  std::string hover = ReadFile(dir / "hover.textproto");
  hover.replace(hover.find("upper: 1e-06"), 12, "upper: 0.05");
  std::ofstream(dir / "hover.textproto", std::ios::trunc) << hover;
  const fs::path out = dir / "out";
  const CliResult again =
      Cli({"sweep", (dir / "sweep.textproto").string(), "--out", out.string(), "--jobs", "1"});
  EXPECT_EQ(again.exit_code, 0) << again.err << again.out;
  EXPECT_FALSE(fs::exists(out / "runs"));
  EXPECT_FALSE(fs::exists(out / ".previous-sweep"));
  EXPECT_EQ(ReadFile(out / "failing.txt"), "");
}

}  // namespace
}  // namespace hilrig::host
