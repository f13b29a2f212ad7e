#include "rig/file_io.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <ostream>
#include <set>

#include "tests/support/test_files.h"

namespace hilrig::rig {
namespace {

namespace fs = std::filesystem;
using host::FreshTestDir;
using host::ReadFile;

void Write(const fs::path& path, const std::string& text) {
  ASSERT_TRUE(WriteFileAtomically(path.string(), text));
}

TEST(ReadRegularFileTest, ReadsARegularFileWhole) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "spec", "name: \"x\"\n");
  auto read = ReadRegularFile((dir / "spec").string(), 100);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(read.value(), "name: \"x\"\n");
}

TEST(ReadRegularFileTest, RefusesAFileAboveTheCapWithoutQuotingIt) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "big", std::string(101, 'q'));
  auto read = ReadRegularFile((dir / "big").string(), 100);
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("larger than 100 bytes"), std::string::npos);
  EXPECT_NE(read.error().message.find((dir / "big").string()), std::string::npos);
  EXPECT_EQ(read.error().message.find("qqq"), std::string::npos);
}

TEST(ReadRegularFileTest, RefusesAFifoWithoutBlocking) {
  const fs::path dir = FreshTestDir("file_io_");
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto read = ReadRegularFile(fifo.string(), 100);  // no writer: a blocking open would hang
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("a FIFO"), std::string::npos) << read.error().message;
}

TEST(ReadRegularFileTest, RefusesDevicesAndFolders) {
  auto zero = ReadRegularFile("/dev/zero", 1 << 20);
  ASSERT_FALSE(zero);
  EXPECT_NE(zero.error().message.find("a device"), std::string::npos) << zero.error().message;
  auto folder = ReadRegularFile(FreshTestDir("file_io_").string(), 100);
  ASSERT_FALSE(folder);
  EXPECT_NE(folder.error().message.find("a folder"), std::string::npos);
}

TEST(ReadRegularFileTest, NamesAMissingFileAndTheCause) {
  auto read = ReadRegularFile("/nonexistent/spec.textproto", 100);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error().message,
            "cannot read /nonexistent/spec.textproto: No such file or directory");
}

// A header is read without reading the rest, with the same refusals as a whole read.
TEST(ReadRegularFileHeadTest, ReadsTheFirstBytesOfARegularFileOnly) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "entry", "HRCACHER and the rest");
  Write(dir / "short", "HR");
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);

  auto head = ReadRegularFileHead((dir / "entry").string(), 8);
  ASSERT_TRUE(head) << head.error().message;
  EXPECT_EQ(head.value(), "HRCACHER");
  EXPECT_EQ(ReadRegularFileHead((dir / "short").string(), 8).value(), "HR");
  auto fifo = ReadRegularFileHead((dir / "pipe").string(), 8);
  ASSERT_FALSE(fifo);
  EXPECT_NE(fifo.error().message.find("a FIFO"), std::string::npos) << fifo.error().message;
  EXPECT_FALSE(ReadRegularFileHead(dir.string(), 8));
  EXPECT_FALSE(ReadRegularFileHead("/dev/zero", 8));
}

TEST(TemporaryNameBesideTest, IsUnpredictable) {
  std::set<std::string> names;
  for (int i = 0; i < 50; ++i) names.insert(TemporaryNameBeside("/x/report.json"));
  EXPECT_EQ(names.size(), 50u);
  EXPECT_EQ(names.begin()->rfind("/x/report.json.tmp-", 0), 0u);
}

TEST(WriteFileAtomicallyTest, ReplacesAPlantedSymlinkAndLeavesItsTargetAlone) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "victim", "precious");
  fs::create_symlink(dir / "victim", dir / "report.json");
  Write(dir / "report.json", "new");
  EXPECT_EQ(ReadFile(dir / "victim"), "precious");
  EXPECT_FALSE(fs::is_symlink(dir / "report.json"));
  EXPECT_EQ(ReadFile(dir / "report.json"), "new");
}

TEST(WriteFileAtomicallyTest, AFailureNamesTheFileAndLeavesNoTemporary) {
  const fs::path dir = FreshTestDir("file_io_");
  fs::create_directory(dir / "taken");  // rename over a non-empty folder fails
  Write(dir / "taken" / "inside", "x");
  auto written = WriteFileAtomically((dir / "taken").string(), "y");
  ASSERT_FALSE(written);
  EXPECT_EQ(written.error().message.rfind("cannot write " + (dir / "taken").string() + ": ", 0),
            0u);
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(OutputFileTest, WritesThroughItsBuffer) {
  const fs::path dir = FreshTestDir("file_io_");
  auto file = OutputFile::Create((dir / "trace.csv").string(), 16);
  ASSERT_TRUE(file) << file.error().message;
  file.value()->stream() << "t,x\n" << std::string(100, 'a') << "\n" << 1.5 << "\n";
  ASSERT_TRUE(file.value()->Close());
  EXPECT_EQ(ReadFile(dir / "trace.csv"), "t,x\n" + std::string(100, 'a') + "\n1.5\n");
}

TEST(OutputFileTest, DoesNotFollowAPlantedSymlink) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "victim", "precious");
  fs::create_symlink(dir / "victim", dir / "can.log");
  auto file = OutputFile::Create((dir / "can.log").string());
  ASSERT_FALSE(file);
  EXPECT_NE(file.error().message.find("symbolic link"), std::string::npos);
  EXPECT_EQ(ReadFile(dir / "victim"), "precious");
}

// A disk that fills: the first failed write is kept with its cause (ENOSPC, as /dev/full gives
// every write), and no later write hides it.
TEST(FdStreamBufTest, AFullDiskKeepsTheCauseOfTheFirstFailedWrite) {
  const int fd = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  FdStreamBuf buffer(fd, 64);
  std::ostream out(&buffer);
  out << std::string(1000, 'x');
  EXPECT_FALSE(buffer.Close());
  EXPECT_EQ(buffer.error_number(), ENOSPC);
  EXPECT_EQ(WriteError("trace.csv", buffer.error_number()).message,
            "cannot write trace.csv: No space left on device");
}

// A FIFO where a trace goes would block the run until someone reads it; a device would swallow
// the trace. Both are refused at once, the FIFO with or without a reader.
TEST(OutputFileTest, RefusesAFifoAndADeviceWithoutBlocking) {
  const fs::path dir = FreshTestDir("file_io_");
  ASSERT_EQ(::mkfifo((dir / "trace.csv").c_str(), 0600), 0);
  auto fifo = OutputFile::Create((dir / "trace.csv").string());
  ASSERT_FALSE(fifo);
  EXPECT_EQ(fifo.error().message,
            "cannot write " + (dir / "trace.csv").string() + ": a FIFO, not a regular file");
  const int reader = ::open((dir / "trace.csv").c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  auto read_fifo = OutputFile::Create((dir / "trace.csv").string());
  ::close(reader);
  ASSERT_FALSE(read_fifo);
  EXPECT_NE(read_fifo.error().message.find("a FIFO, not a regular file"), std::string::npos);
  auto device = OutputFile::Create("/dev/null");
  ASSERT_FALSE(device);
  EXPECT_EQ(device.error().message, "cannot write /dev/null: a device, not a regular file");
}

TEST(OutputFileTest, TruncatesARegularFileItReplaces) {
  const fs::path dir = FreshTestDir("file_io_");
  Write(dir / "trace.csv", "an earlier, longer trace\n");
  auto file = OutputFile::Create((dir / "trace.csv").string());
  ASSERT_TRUE(file) << file.error().message;
  file.value()->stream() << "t\n";
  ASSERT_TRUE(file.value()->Close());
  EXPECT_EQ(ReadFile(dir / "trace.csv"), "t\n");
}

}  // namespace
}  // namespace hilrig::rig
