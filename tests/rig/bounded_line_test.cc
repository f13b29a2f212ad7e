#include "rig/bounded_line.h"

#include <gtest/gtest.h>

#include <sstream>

namespace hilrig::rig {
namespace {

TEST(ReadBoundedLineTest, ReadsLinesWithAndWithoutAFinalNewline) {
  std::istringstream in("one\n\nthree");
  std::string line;
  ASSERT_EQ(ReadBoundedLine(in, 8, line), LineRead::kLine);
  EXPECT_EQ(line, "one");
  ASSERT_EQ(ReadBoundedLine(in, 8, line), LineRead::kLine);
  EXPECT_EQ(line, "");
  ASSERT_EQ(ReadBoundedLine(in, 8, line), LineRead::kLine);
  EXPECT_EQ(line, "three");
  EXPECT_EQ(ReadBoundedLine(in, 8, line), LineRead::kEnd);
  EXPECT_EQ(ReadBoundedLine(in, 8, line), LineRead::kEnd);
}

TEST(ReadBoundedLineTest, TakesALineOfExactlyTheCap) {
  for (const std::string tail : {"\n", ""}) {
    std::istringstream in("12345678" + tail);
    std::string line;
    ASSERT_EQ(ReadBoundedLine(in, 8, line), LineRead::kLine) << tail.size();
    EXPECT_EQ(line, "12345678");
    EXPECT_EQ(ReadBoundedLine(in, 8, line), LineRead::kEnd);
  }
}

TEST(ReadBoundedLineTest, RefusesALineOneByteLongerOrMore) {
  for (const std::string text : {"123456789", "123456789\n", "1234567890abc\nnext\n"}) {
    std::istringstream in(text);
    std::string line;
    EXPECT_EQ(ReadBoundedLine(in, 8, line), LineRead::kTooLong) << text;
    EXPECT_LE(line.capacity(), std::size_t{64}) << text;
  }
}

TEST(ReadBoundedLineTest, KeepsNulBytesInsideALine) {
  std::istringstream in(std::string("a\0b\n", 4));
  std::string line;
  ASSERT_EQ(ReadBoundedLine(in, 8, line), LineRead::kLine);
  EXPECT_EQ(line, std::string("a\0b", 3));
}

TEST(ReadBoundedLineTest, AFailedStreamIsAReadError) {
  std::istringstream in("line\n");
  in.setstate(std::ios::badbit);
  std::string line;
  EXPECT_EQ(ReadBoundedLine(in, 8, line), LineRead::kReadError);
}

}  // namespace
}  // namespace hilrig::rig
