#include "host/link/child_process.h"

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
