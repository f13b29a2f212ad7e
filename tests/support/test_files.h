// Files for tests that run commands and read what they wrote: a fresh folder per test (named after
// the running test, so parallel tests never share one), a whole file read back as text, a file
// damaged in one byte, a user's files in a cache folder, and a folder that cannot be made.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hilrig::host {

// The whole file, or "" when it cannot be read.
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// Flips bits of the byte at `offset` from the end of the file (1 is the last byte), as damage on a
// disk or a careless edit would.
inline void ChangeByteFromEnd(const std::filesystem::path& path, std::size_t offset,
                              unsigned char flip = 0x40) {
  std::string bytes = ReadFile(path);
  ASSERT_GE(bytes.size(), offset) << path;
  bytes[bytes.size() - offset] = static_cast<char>(bytes[bytes.size() - offset] ^ flip);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// An empty folder under the test temp dir: `prefix` followed by the running test's name.
inline std::filesystem::path FreshTestDir(const std::string& prefix) {
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) /
      (prefix + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A user's files in a cache folder, a day old, none written by the cache: `count` named
// *<extension>, one named like an entry (16 hex digits) and one like an entry's temporary file.
inline std::vector<std::filesystem::path> PlantUserFiles(const std::filesystem::path& dir,
                                                         const std::string& extension, int count) {
  std::vector<std::filesystem::path> files;
  for (int i = 0; i < count; ++i) files.push_back(dir / ("user_" + std::to_string(i) + extension));
  files.push_back(dir / ("fedcba9876543210" + extension));
  files.push_back(dir / ("notes" + extension + ".tmp-0123456789abcdef"));
  for (const std::filesystem::path& file : files) {
    std::ofstream(file) << "the user's";
    std::filesystem::last_write_time(
        file, std::filesystem::last_write_time(file) - std::chrono::hours(24));
  }
  return files;
}

// A folder path that cannot be created: a regular file stands where its parent should be (in a
// fresh test folder named with `prefix`). For testing writes that must fail.
inline std::filesystem::path UncreatableFolder(const std::string& prefix) {
  const std::filesystem::path blocker = FreshTestDir(prefix) / "blocker";
  std::ofstream(blocker) << "a file where the folder should be";
  return blocker / "folder";
}

}  // namespace hilrig::host
