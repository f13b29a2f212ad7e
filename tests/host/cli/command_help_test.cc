#include "host/cli/command_help.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <string>
#include <vector>

#include "host/cli/build_info.h"
#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

int Lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// `hilrig help CMD` and `hilrig CMD --help` print that command's usage, and only that: every
// command's synopsis names the command, none prints the overview.
TEST(CommandHelpTest, EveryCommandHasItsOwnHelpByBothRoutes) {
  for (const CommandHelp& command : Commands()) {
    const std::string name(command.name);
    const CliResult help = Cli({"help", name});
    EXPECT_EQ(help.exit_code, kExitPass) << name;
    EXPECT_THAT(help.out, HasSubstr("hilrig " + name)) << name;
    EXPECT_THAT(help.out, Not(HasSubstr("commands:"))) << name;
    if (name == "help") continue;
    for (const char* flag : {"--help", "-h"}) {
      const CliResult own = Cli({name, flag});
      EXPECT_EQ(own.exit_code, kExitPass) << name << " " << flag;
      EXPECT_EQ(own.out, help.out) << name << " " << flag;
    }
  }
}

// `check --help` once read a file called --help; a help flag after other arguments is still one.
TEST(CommandHelpTest, HelpAmongOtherArgumentsIsHelpNotAFile) {
  const CliResult check = Cli({"check", "spec.textproto", "--help"});
  EXPECT_EQ(check.exit_code, kExitPass);
  EXPECT_THAT(check.out, HasSubstr("hilrig check FILE.textproto"));
  EXPECT_EQ(check.err, "");
}

TEST(CommandHelpTest, TheOverviewListsEveryCommandAndHowToGetItsHelp) {
  const CliResult help = Cli({"help"});
  EXPECT_EQ(help.exit_code, kExitPass);
  for (const CommandHelp& command : Commands())
    EXPECT_THAT(help.out, HasSubstr(std::string(command.name)));
  EXPECT_THAT(help.out, HasSubstr("hilrig help COMMAND"));
  EXPECT_THAT(help.out, HasSubstr("Exit codes"));
}

TEST(CommandHelpTest, VersionNamesTheCommitAndBuildType) {
  const CliResult version = Cli({"--version"});
  EXPECT_EQ(version.exit_code, kExitPass);
  EXPECT_EQ(version.out, VersionLine() + "\n");
  EXPECT_TRUE(std::regex_match(std::string(ThisBuild().commit),
                               std::regex("[0-9a-f]{12}(-dirty)?|unknown")))
      << ThisBuild().commit;
  EXPECT_STRNE(ThisBuild().build_type, "");
}

// A usage error is its reason on one line and where the help is on the next, with the nearest
// name for a misspelt option or command.
TEST(CommandHelpTest, AUsageErrorIsOneLineAndAPointerToTheHelp) {
  const CliResult option = Cli({"run", "spec.textproto", "--sed", "3"});
  EXPECT_EQ(option.exit_code, kExitBadInput);
  EXPECT_EQ(option.err,
            "hilrig run: unknown option --sed (did you mean --seed?)\nsee `hilrig help run`\n");
  const CliResult command = Cli({"rnu"});
  EXPECT_EQ(command.exit_code, kExitBadInput);
  EXPECT_EQ(command.err,
            "hilrig: unknown command \"rnu\" (did you mean run?)\nsee `hilrig help`\n");
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"bench", "--quick", "--bogus", "1"},
                                             {"compare", "a"},
                                             {"sweep"},
                                             {"check"},
                                             {"help", "fly"}}) {
    const CliResult result = Cli(args);
    EXPECT_EQ(result.exit_code, kExitBadInput) << args[0];
    EXPECT_EQ(Lines(result.err), 2) << result.err;
    EXPECT_THAT(result.err, HasSubstr("see `hilrig help")) << args[0];
  }
}

}  // namespace
}  // namespace hilrig::host
