// `hilrig check` on specs that are valid but costly: a run that would fill a disk is named with
// its estimated size, and the spec is still accepted.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/cli_runner.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

TEST(CliCheckTest, WarnsOfARunWhoseFilesWouldFillADiskAndStillAcceptsIt) {
  const auto dir = FreshTestDir("cli_check_size");
  std::ofstream(dir / "day.textproto")
      << "name: \"day\"\nsimulation { duration_s: 86400 trace_rate_hz: 1000 }\n";
  const CliResult check = Cli({"check", (dir / "day.textproto").string()});
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_THAT(check.out, HasSubstr("day.textproto: ok"));
  EXPECT_THAT(check.err, HasSubstr("day.textproto: warning: a run writes about 79.8 GB"));
  EXPECT_THAT(check.err, HasSubstr("run.mcap 43.3 GB"));
}

// What hilrig prints may quote a file name (or a board's name, a peer's reason): the process lets
// no control character through to the terminal.
TEST(CliCheckTest, AFileNameWithAnEscapeSequenceIsPrintedEscaped) {
  const auto dir = FreshTestDir("cli_check_escape");
  const std::string name = (dir / "x\x1b[2Jy.textproto").string();
  const ProcessResult result = RunHilrig("check '" + name + "'", dir / "err");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("x\\x1b[2Jy.textproto"));
  EXPECT_EQ(result.err.find('\x1b'), std::string::npos);
}

}  // namespace
}  // namespace hilrig::host
