// A file read a line at a time: only a regular file opens (a FIFO or a device is refused without
// blocking), and a line past the cap is reported, never held whole.
#include "rig/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "tests/support/test_files.h"

namespace hilrig::rig {
namespace {

namespace fs = std::filesystem;

TEST(InputFileTest, ReadsLinesOfARegularFile) {
  const fs::path dir = host::FreshTestDir("input_file_");
  std::ofstream(dir / "rows") << "first\nsecond\nlast without a newline";
  auto file = InputFile::Open((dir / "rows").string(), 4);  // a buffer smaller than a line
  ASSERT_TRUE(file) << file.error().message;
  std::string line;
  ASSERT_EQ(file.value()->ReadLine(100, line), LineRead::kLine);
  EXPECT_EQ(line, "first");
  ASSERT_EQ(file.value()->ReadLine(100, line), LineRead::kLine);
  EXPECT_EQ(line, "second");
  ASSERT_EQ(file.value()->ReadLine(100, line), LineRead::kLine);
  EXPECT_EQ(line, "last without a newline");
  EXPECT_EQ(file.value()->ReadLine(100, line), LineRead::kEnd);
}

TEST(InputFileTest, RefusesAFifoAndADeviceWithoutBlocking) {
  const fs::path dir = host::FreshTestDir("input_file_");
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  auto fifo = InputFile::Open((dir / "pipe").string());
  ASSERT_FALSE(fifo);
  EXPECT_EQ(fifo.error().message,
            "cannot read " + (dir / "pipe").string() + ": a FIFO, not a regular file");
  fs::create_symlink("/dev/zero", dir / "zero");
  auto zero = InputFile::Open((dir / "zero").string());
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().message,
            "cannot read " + (dir / "zero").string() + ": a device, not a regular file");
}

TEST(InputFileTest, ALineLongerThanTheCapIsReportedNotHeld) {
  const fs::path dir = host::FreshTestDir("input_file_");
  std::ofstream(dir / "endless") << std::string(1 << 20, 'z');
  auto file = InputFile::Open((dir / "endless").string());
  ASSERT_TRUE(file) << file.error().message;
  std::string line;
  EXPECT_EQ(file.value()->ReadLine(1000, line), LineRead::kTooLong);
  EXPECT_LE(line.capacity(), 4096u);
}

}  // namespace
}  // namespace hilrig::rig
