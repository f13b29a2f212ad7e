// Files for tests that run commands and read what they wrote: a fresh folder per test (named after
// the running test, so parallel tests never share one), a whole file read back as text, a file
// damaged in one byte, and a folder that cannot be made.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

// A folder path that cannot be created: a regular file stands where its parent should be (in a
// fresh test folder named with `prefix`). For testing writes that must fail.
inline std::filesystem::path UncreatableFolder(const std::string& prefix) {
  const std::filesystem::path blocker = FreshTestDir(prefix) / "blocker";
  std::ofstream(blocker) << "a file where the folder should be";
  return blocker / "folder";
}

}  // namespace hilrig::host
