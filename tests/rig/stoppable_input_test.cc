#include "rig/stoppable_input.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <istream>
#include <string>

namespace hilrig::rig {
namespace {

// A pipe whose write end the test holds open, so that reading it past what was written would
// wait.
class PipeTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(::pipe(fds_), 0); }
  void TearDown() override {
    ::close(fds_[0]);
    if (fds_[1] >= 0) ::close(fds_[1]);
  }
  void Write(const std::string& text) {
    ASSERT_EQ(::write(fds_[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
  }
  void CloseWriteEnd() {
    ::close(fds_[1]);
    fds_[1] = -1;
  }
  int read_end() const { return fds_[0]; }

 private:
  int fds_[2] = {-1, -1};
};

TEST_F(PipeTest, HandsOutLinesAndALastLineWithoutItsNewline) {
  Write("1 2 3\n4 5 6\n7 8");
  CloseWriteEnd();
  StoppableLineBuf lines(read_end(), nullptr);
  std::istream in(&lines);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "1 2 3");
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "4 5 6");
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "7 8");
  EXPECT_FALSE(std::getline(in, line));
  EXPECT_FALSE(lines.stopped());
  EXPECT_EQ(lines.error_number(), 0);
}

// The writer is still there and has not finished its line: a stop ends the input at once, and
// the half line is not read as a shorter one ("1e-3 2e-3 3e-3" of "1e-3 2e-3 3e-35").
TEST_F(PipeTest, AStopEndsTheWaitAndDropsTheUnfinishedLine) {
  Write("1 2 3\n1e-3 2e-3 3e-3");
  std::atomic<bool> stop_requested{false};
  StoppableLineBuf lines(read_end(), &stop_requested);
  std::istream in(&lines);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "1 2 3");
  stop_requested = true;
  EXPECT_FALSE(std::getline(in, line));
  EXPECT_TRUE(lines.stopped());
}

// Standard input closed by whoever started the process.
TEST(StoppableLineBufTest, AFailedReadEndsTheInputWithItsCause) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ::close(fds[0]);
  ::close(fds[1]);
  for (const int fd : {fds[0], -1}) {
    StoppableLineBuf lines(fd, nullptr);
    std::istream in(&lines);
    std::string line;
    EXPECT_FALSE(std::getline(in, line));
    EXPECT_EQ(lines.error_number(), EBADF) << fd;
  }
}

}  // namespace
}  // namespace hilrig::rig
