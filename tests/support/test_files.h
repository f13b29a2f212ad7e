// Files for tests that run commands and read what they wrote: a fresh folder per test (named after
// the running test, so parallel tests never share one), a whole file read back as text, and a
// folder that cannot be made.
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
