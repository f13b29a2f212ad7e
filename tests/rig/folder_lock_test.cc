#include "rig/folder_lock.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "rig/file_io.h"
#include "tests/support/test_files.h"

namespace hilrig::rig {
namespace {

namespace fs = std::filesystem;
using host::FreshTestDir;
using host::ReadFile;
using ::testing::HasSubstr;
using ::testing::Not;

TEST(FolderLockTest, MakesTheFolderAndWritesItsHolderIntoTheLockFile) {
  const fs::path folder = FreshTestDir("folder_lock_") / "a" / "b";
  auto lock = FolderLock::Acquire(folder.string());
  ASSERT_TRUE(lock) << lock.error().message;
  EXPECT_THAT(ReadFile(folder / kFolderLockFileName),
              HasSubstr("pid " + std::to_string(::getpid()) + "\n"));
}

// flock(2) locks belong to the open file: a second Acquire conflicts even from the same process,
// as it would from another.
TEST(FolderLockTest, ASecondHolderIsRefusedWithTheFirstOnesPid) {
  const fs::path folder = FreshTestDir("folder_lock_");
  auto first = FolderLock::Acquire(folder.string());
  ASSERT_TRUE(first) << first.error().message;
  auto second = FolderLock::Acquire(folder.string());
  ASSERT_FALSE(second);
  EXPECT_THAT(second.error().message, HasSubstr(folder.string() + " is in use"));
  EXPECT_THAT(second.error().message, HasSubstr("pid " + std::to_string(::getpid()) + " ("));
}

TEST(FolderLockTest, TheFolderIsFreeAgainOnceTheHolderIsGone) {
  const fs::path folder = FreshTestDir("folder_lock_");
  { auto first = FolderLock::Acquire(folder.string()); }
  auto moved = FolderLock::Acquire(folder.string());
  ASSERT_TRUE(moved);
  FolderLock holder = std::move(moved).value();
  EXPECT_FALSE(FolderLock::Acquire(folder.string())) << "the moved-to lock still holds it";
}

// A planted lock file held by someone else: its text never reaches the message.
TEST(FolderLockTest, AHoldersLockFileIsNeverQuoted) {
  const fs::path folder = FreshTestDir("folder_lock_");
  const fs::path path = folder / kFolderLockFileName;
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  const std::string planted = "\x1b]0;secret words\x07\n";
  ASSERT_EQ(::write(fd, planted.data(), planted.size()), static_cast<ssize_t>(planted.size()));
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  auto lock = FolderLock::Acquire(folder.string());
  ::close(fd);
  ASSERT_FALSE(lock);
  EXPECT_THAT(lock.error().message, HasSubstr("does not give"));
  EXPECT_THAT(lock.error().message, Not(HasSubstr("secret")));
}

TEST(FolderLockTest, ASymbolicLinkAtTheLockNameIsRefusedNotFollowed) {
  const fs::path folder = FreshTestDir("folder_lock_");
  const fs::path target = folder / "target";
  ASSERT_TRUE(WriteFileAtomically(target.string(), "keep"));
  fs::create_symlink(target, folder / kFolderLockFileName);
  auto lock = FolderLock::Acquire(folder.string());
  ASSERT_FALSE(lock);
  EXPECT_THAT(lock.error().message, HasSubstr("symbolic link"));
  EXPECT_EQ(ReadFile(target), "keep");
}

TEST(FolderLockTest, AFifoAtTheLockNameIsRefusedWithoutBlocking) {
  const fs::path folder = FreshTestDir("folder_lock_");
  ASSERT_EQ(::mkfifo((folder / kFolderLockFileName).c_str(), 0644), 0);
  auto lock = FolderLock::Acquire(folder.string());
  ASSERT_FALSE(lock);
  EXPECT_THAT(lock.error().message, HasSubstr("not a regular file"));
}

TEST(FolderLockTest, AFolderThatCannotBeMadeIsAnErrorNamingIt) {
  const fs::path folder = host::UncreatableFolder("folder_lock_");
  auto lock = FolderLock::Acquire(folder.string());
  ASSERT_FALSE(lock);
  EXPECT_THAT(lock.error().message, HasSubstr("cannot create " + folder.string()));
}

}  // namespace
}  // namespace hilrig::rig
