#include "host/link/child_process.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

namespace hilrig::host {
namespace {

// What only the child may know travels in its environment and replaces a variable of the same
// name that this process has.
TEST(ChildProcessTest, EnvironmentGoesToTheChildOnly) {
  ASSERT_EQ(::setenv("HILRIG_CHILD_TEST_SECRET", "parent", 1), 0);
  auto child = ChildProcess::Spawn(
      {"/bin/sh", "-c", "test \"$HILRIG_CHILD_TEST_SECRET\" = child && test -n \"$PATH\""},
      {"HILRIG_CHILD_TEST_SECRET=child"});
  ASSERT_TRUE(child.ok()) << child.error().message;
  int status = 0;
  ASSERT_EQ(::waitpid(child.value().pid(), &status, 0), child.value().pid());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_STREQ(::getenv("HILRIG_CHILD_TEST_SECRET"), "parent");
  ::unsetenv("HILRIG_CHILD_TEST_SECRET");
}

int ExitStatusOf(ChildProcess& child) {
  int status = 0;
  EXPECT_EQ(::waitpid(child.pid(), &status, 0), child.pid());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A close-on-exec descriptor reaches the child only when it is named to be inherited.
TEST(ChildProcessTest, InheritsOnlyTheNamedDescriptors) {
  int fds[2];
  ASSERT_EQ(::pipe2(fds, O_CLOEXEC), 0);
  const std::string probe = "test -e /proc/self/fd/" + std::to_string(fds[0]);
  auto inherited = ChildProcess::Spawn({"/bin/sh", "-c", probe}, {}, {fds[0]});
  ASSERT_TRUE(inherited.ok()) << inherited.error().message;
  EXPECT_EQ(ExitStatusOf(inherited.value()), 0);
  auto closed = ChildProcess::Spawn({"/bin/sh", "-c", probe});
  ASSERT_TRUE(closed.ok()) << closed.error().message;
  EXPECT_EQ(ExitStatusOf(closed.value()), 1);
  ::close(fds[0]);
  ::close(fds[1]);
}

TEST(RunCapturingOutputTest, KeepsStandardOutputAndTheExitStatus) {
  auto ran = RunCapturingOutput({"/bin/sh", "-c", "echo 4711; echo noise >&2; exit 3"}, nullptr);
  ASSERT_TRUE(ran.ok()) << ran.error().message;
  EXPECT_EQ(ran.value().output, "4711\n");
  EXPECT_EQ(ran.value().exit_status, 3);
  EXPECT_EQ(ran.value().ended, "exited with status 3");
  // More output than is kept: the rest is read and dropped, and the child still ends.
  auto long_output =
      RunCapturingOutput({"/bin/sh", "-c", "head -c 200000 /dev/zero | tr '\\0' x"}, nullptr, 10);
  ASSERT_TRUE(long_output.ok());
  EXPECT_EQ(long_output.value().output, "xxxxxxxxxx");
  EXPECT_EQ(long_output.value().exit_status, 0);
  auto missing = RunCapturingOutput({"/nonexistent/program"}, nullptr);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("cannot start /nonexistent/program"), std::string::npos);
}

TEST(RunCapturingOutputTest, AStopRequestEndsTheChild) {
  const std::atomic<bool> stop{true};
  auto ran = RunCapturingOutput({"/bin/sleep", "30"}, &stop);
  ASSERT_TRUE(ran.ok()) << ran.error().message;
  EXPECT_FALSE(ran.value().exit_status.has_value());
  EXPECT_EQ(ran.value().ended, "killed by signal 15");
}

TEST(FindInPathTest, FindsAnExecutableAndNamesAMissingOne) {
  auto shell = FindInPath("sh");
  ASSERT_TRUE(shell) << shell.error().message;
  EXPECT_EQ(shell.value().substr(shell.value().size() - 3), "/sh");
  EXPECT_EQ(::access(shell.value().c_str(), X_OK), 0);
  auto missing = FindInPath("hilrig-no-such-program");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, "no hilrig-no-such-program in PATH");
}

}  // namespace
}  // namespace hilrig::host
