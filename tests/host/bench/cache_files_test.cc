#include "host/bench/cache_files.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// Ages an entry by `minutes`, so the order of use does not rest on the file system's clock grain.
void MakeOlder(const CacheFolder& folder, const std::string& key, int minutes) {
  fs::last_write_time(folder.PathOf(key),
                      fs::file_time_type::clock::now() - std::chrono::minutes(minutes));
}

// Every rebuild keys a new set of entries, so the folders are bounded: a store past the bound
// removes the entries used least recently, a load counts as a use, and files of other kinds in
// the folder are left alone.
TEST(CacheFolderTest, AStorePastTheBoundRemovesTheLeastRecentlyUsedEntries) {
  const std::string dir = ::testing::TempDir() + "/cache_folder_test";
  fs::remove_all(dir);
  const CacheFolder folder(dir, ".entry", 3);
  for (const char* key : {"a", "b", "c"}) ASSERT_TRUE(folder.Store(key, key).ok());
  MakeOlder(folder, "a", 30);
  MakeOlder(folder, "b", 20);
  MakeOlder(folder, "c", 10);
  std::ofstream(dir + "/notes.txt") << "not an entry";

  ASSERT_EQ(folder.Load("a"), "a");  // a is now the most recently used
  ASSERT_TRUE(folder.Store("d", "d").ok());

  EXPECT_EQ(folder.Load("a"), "a");
  EXPECT_FALSE(folder.Load("b").has_value()) << "the least recently used goes first";
  EXPECT_EQ(folder.Load("c"), "c");
  EXPECT_EQ(folder.Load("d"), "d");
  EXPECT_TRUE(fs::exists(dir + "/notes.txt"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hilrig::host
