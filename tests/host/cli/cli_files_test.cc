// What hilrig does with a damaged file system around it: links that loop or point nowhere in a
// scenario folder, an output path that is a file, links planted where outputs go.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr const char* kLoopMessage = "Too many levels of symbolic links";
constexpr const char* kShortSpec = R"(name: "short"
simulation { duration_s: 0.5 }
envelopes { name: "grounded" signal: ALTITUDE_M upper: 0.01 }
)";

class CliFilesTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = FreshTestDir("hilrig_cli_files_"); }
  fs::path Write(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path;
  }
  // A link that points at itself: every attempt to follow it fails with ELOOP.
  fs::path Loop(const fs::path& path) {
    fs::create_directories(path.parent_path());
    fs::create_symlink(path.filename(), path);
    return path;
  }
  CliResult Run(const fs::path& target, const fs::path& out) {
    return Cli({"run", target.string(), "--no-reference", "--out", out.string()});
  }
  fs::path dir_;
};

TEST_F(CliFilesTest, ALinkLoopInAScenarioFolderIsNamedAndTheOtherScenariosRun) {
  const fs::path folder = dir_ / "scenarios";
  Write(folder / "a_short.textproto", kShortSpec);
  Loop(folder / "elsewhere");  // not a spec: never looked at
  const fs::path loop = Loop(folder / "b_loop.textproto");
  const CliResult result = Run(folder, dir_ / "out");
  EXPECT_EQ(result.exit_code, kExitBadInput) << result.err;
  EXPECT_THAT(result.err, HasSubstr("cannot read " + loop.string() + ": " + kLoopMessage));
  EXPECT_THAT(result.out, HasSubstr("INVALID"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "a_short" / "report.json"));
}

TEST_F(CliFilesTest, ALinkLoopThatIsNoSpecLeavesTheFolderRunAlone) {
  const fs::path folder = dir_ / "scenarios";
  Write(folder / "a_short.textproto", kShortSpec);
  Loop(folder / "elsewhere");
  const CliResult result = Run(folder, dir_ / "out");
  EXPECT_EQ(result.exit_code, kExitPass) << result.err;
}

TEST_F(CliFilesTest, ADanglingLinkNamedAsASpecIsAnErrorNotSkipped) {
  const fs::path folder = dir_ / "scenarios";
  Write(folder / "a_short.textproto", kShortSpec);
  fs::create_symlink("nowhere.textproto", folder / "b_gone.textproto");
  const CliResult result = Run(folder, dir_ / "out");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("cannot read " + (folder / "b_gone.textproto").string() +
                                    ": No such file or directory"));
}

TEST_F(CliFilesTest, ALinkLoopAsTheTargetIsNamedWithItsCause) {
  const fs::path loop = Loop(dir_ / "loop.textproto");
  for (const std::string command : {"run", "check"}) {
    const CliResult result = Cli({command, loop.string()});
    EXPECT_EQ(result.exit_code, kExitBadInput) << command;
    EXPECT_THAT(result.err, HasSubstr(loop.string())) << command;
    EXPECT_THAT(result.err, HasSubstr(kLoopMessage)) << command << result.err;
  }
}

TEST_F(CliFilesTest, AFolderThatCannotBeListedIsNamed) {
  if (::geteuid() == 0) GTEST_SKIP() << "root lists any folder";
  const fs::path folder = dir_ / "locked";
  Write(folder / "a_short.textproto", kShortSpec);
  fs::permissions(folder, fs::perms::owner_exec);  // searchable, not readable
  const CliResult result = Run(folder, dir_ / "out");
  fs::permissions(folder, fs::perms::owner_all);
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("cannot list folder " + folder.string()));
}

TEST_F(CliFilesTest, AnOutputFolderThatIsAFileIsNamed) {
  const fs::path spec = Write(dir_ / "short.textproto", kShortSpec);
  const fs::path file = Write(dir_ / "a_file", "not a folder");
  const CliResult result = Run(spec, file);
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("cannot create " + file.string() + ": Not a directory"));
}

TEST_F(CliFilesTest, AnOutputThatCannotBeWrittenIsNamedWithTheCause) {
  const fs::path spec = Write(dir_ / "short.textproto", kShortSpec);
  for (const char* file : {"trace.csv", "can.log", "report.json", "junit.xml", "index.html"}) {
    const fs::path out = dir_ / (std::string("out_") + file);
    Write(out / file / "in_the_way", "a folder stands where the file goes");
    const CliResult result = Run(spec, out);
    EXPECT_EQ(result.exit_code, kExitBadInput) << file;
    EXPECT_THAT(result.err, HasSubstr("cannot write " + (out / file).string() + ": Is a directory"))
        << result.err;
  }
}

// A FIFO where the trace or the CAN log goes would block the run until someone reads it: refused
// at once, by name (a separate process, bounded, so a hang fails the test instead of hanging it).
TEST_F(CliFilesTest, AFifoWhereATraceOrLogGoesIsRefusedAtOnce) {
  const fs::path spec = Write(dir_ / "short.textproto", kShortSpec);
  for (const char* file : {"trace.csv", "can.log"}) {
    const fs::path out = dir_ / (std::string("fifo_") + file);
    fs::create_directories(out);
    ASSERT_EQ(::mkfifo((out / file).c_str(), 0600), 0);
    const ProcessResult result =
        RunHilrig("run " + spec.string() + " --no-reference --out " + out.string() + " >/dev/null",
                  dir_ / (std::string(file) + ".err"));
    EXPECT_EQ(result.exit_code, kExitBadInput) << result.err;
    EXPECT_THAT(result.err, HasSubstr("cannot write " + (out / file).string() +
                                      ": a FIFO, not a regular file"));
  }
}

TEST_F(CliFilesTest, ALinkPlantedAtTheCanLogIsNotFollowed) {
  const fs::path spec = Write(dir_ / "short.textproto", kShortSpec);
  const fs::path victim = Write(dir_ / "victim.txt", "precious");
  fs::create_directories(dir_ / "out");
  fs::create_symlink(victim, dir_ / "out" / "can.log");
  const CliResult result = Run(spec, dir_ / "out");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr((dir_ / "out" / "can.log").string() +
                                    ": it is a symbolic link, which is not followed"));
  EXPECT_EQ(ReadFile(victim), "precious");
}

TEST_F(CliFilesTest, LinksPlantedAtTheReportAndAtGuessableTemporaryNamesAreNotFollowed) {
  const fs::path spec = Write(dir_ / "short.textproto", kShortSpec);
  const fs::path victim = Write(dir_ / "victim.txt", "precious");
  fs::create_directories(dir_ / "out");
  fs::create_symlink(victim, dir_ / "out" / "report.json");
  // A temporary name made of the path and the process id could be guessed and planted.
  for (const char* file : {"report.json", "junit.xml"}) {
    fs::create_symlink(victim, dir_ / "out" / (file + (".tmp" + std::to_string(::getpid()))));
  }
  const CliResult result = Run(spec, dir_ / "out");
  EXPECT_EQ(result.exit_code, kExitPass) << result.err;
  EXPECT_EQ(ReadFile(victim), "precious");
  EXPECT_FALSE(fs::is_symlink(dir_ / "out" / "report.json"));
  EXPECT_THAT(ReadFile(dir_ / "out" / "report.json"), HasSubstr("\"scenario\": \"short\""));
}

TEST_F(CliFilesTest, BenchNamesALinkLoopAmongAllScenes) {
  const fs::path folder = dir_ / "scenarios";
  Write(folder / "a_short.textproto", kShortSpec);
  const fs::path loop = Loop(folder / "b_loop.textproto");
  const CliResult result = Cli({"bench", "--scenes", "all", "--scenarios", folder.string(),
                                "--quick", "--out", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("cannot read " + loop.string() + ": " + kLoopMessage));
}

TEST_F(CliFilesTest, BenchNamesAScenariosFolderThatIsNone) {
  const fs::path file = Write(dir_ / "a_file", "not a folder");
  const CliResult result = Cli(
      {"bench", "--scenes", "all", "--scenarios", file.string(), "--out", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("cannot list folder " + file.string() + ": Not a directory"));
}

}  // namespace
}  // namespace hilrig::host
