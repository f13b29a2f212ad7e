#include "host/bench/cache_files.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr CacheFormat kFormat{".entry", "HRTESTEN", 1, 3, 1 << 16};

// Any content is an entry's content.
rig::Result<std::string> AsIs(const std::string& content) { return content; }

std::string Key(char c) { return std::string(15, '0') + c; }

// Ages a file by `minutes` from its own time (no clock read), so the order of use does not rest on
// the file system's clock grain.
void MakeOlder(const fs::path& path, int minutes) {
  fs::last_write_time(path, fs::last_write_time(path) - std::chrono::minutes(minutes));
}

// Every rebuild keys a new set of entries, so the folders are bounded: a store past the bound
// removes the entries used least recently, and a load counts as a use.
TEST(CacheFolderTest, AStorePastTheBoundRemovesTheLeastRecentlyUsedEntries) {
  const fs::path dir = FreshTestDir("cache_folder_");
  const CacheFolder folder(dir.string(), kFormat, nullptr);
  for (char key : {'a', 'b', 'c'}) ASSERT_TRUE(folder.Store(Key(key), {&key, 1}).ok());
  MakeOlder(folder.PathOf(Key('a')), 30);
  MakeOlder(folder.PathOf(Key('b')), 20);
  MakeOlder(folder.PathOf(Key('c')), 10);

  ASSERT_EQ(folder.Load(Key('a'), AsIs), "a");  // a is now the most recently used
  ASSERT_TRUE(folder.Store(Key('d'), "d").ok());

  EXPECT_EQ(folder.Load(Key('a'), AsIs), "a");
  EXPECT_FALSE(folder.Load(Key('b'), AsIs).has_value()) << "the least recently used goes first";
  EXPECT_EQ(folder.Load(Key('c'), AsIs), "c");
  EXPECT_EQ(folder.Load(Key('d'), AsIs), "d");
}

// Content the cache would not read back is not written.
TEST(CacheFolderTest, ContentAboveTheBoundIsNotStored) {
  const fs::path dir = FreshTestDir("cache_folder_");
  const CacheFolder folder(dir.string(), kFormat, nullptr);

  const auto stored = folder.Store(Key('a'), std::string(1 << 16, 'x'));

  ASSERT_FALSE(stored);
  EXPECT_NE(stored.error().message.find("more than the cache reads back"), std::string::npos);
  EXPECT_FALSE(fs::exists(folder.PathOf(Key('a'))));
}

// Writers storing one key at once while a reader reads it: every read is a whole entry of one
// writer (each entry is renamed into place whole), never a miss on a damaged one.
TEST(CacheFolderTest, ConcurrentStoresOfOneKeyLeaveWholeEntries) {
  const fs::path dir = FreshTestDir("cache_folder_");
  std::ostringstream notes;
  const CacheFolder folder(dir.string(), kFormat, &notes);
  const auto uniform = [](const std::string& content) -> rig::Result<std::string> {
    if (content.size() != 4096 || content.find_first_not_of(content[0]) != std::string::npos) {
      return rig::MakeError("entries of two writers mixed");
    }
    return content;
  };

  ASSERT_TRUE(folder.Store(Key('a'), std::string(4096, 'o')));
  std::vector<std::thread> writers;
  for (char id : {'p', 'q', 'r', 's'}) {
    writers.emplace_back([&folder, id] {
      for (int i = 0; i < 100; ++i) EXPECT_TRUE(folder.Store(Key('a'), std::string(4096, id)));
    });
  }
  int whole = 0;
  for (int i = 0; i < 400; ++i) whole += folder.Load(Key('a'), uniform).has_value() ? 1 : 0;
  for (std::thread& writer : writers) writer.join();

  EXPECT_EQ(whole, 400);
  EXPECT_EQ(notes.str(), "");
}

}  // namespace
}  // namespace hilrig::host
