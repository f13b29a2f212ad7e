#include "host/cache/cache_files.h"

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

constexpr CacheFormat kFormat{.extension = ".entry",
                              .magic = "HRTESTEN",
                              .legacy_magic = "HRTEST01",
                              .max_entries = 3,
                              .max_entry_bytes = 1 << 16};

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

// Only the cache's own files count and go: names of the entry form that open with its magic, or
// with the magic its entries had before they carried a header.
TEST(CacheFolderTest, TheBoundCountsAndRemovesOnlyTheCachesOwnEntries) {
  const fs::path dir = FreshTestDir("cache_folder_");
  const std::vector<fs::path> users = {dir / "notes.txt", dir / "mine.entry",
                                       dir / (Key('e') + ".entry"), dir / (Key('A') + ".entry")};
  for (const fs::path& user : users) {
    std::ofstream(user) << "the user's";
    MakeOlder(user, 60);
  }
  const fs::path legacy = dir / (Key('f') + ".entry");
  std::ofstream(legacy) << "HRTEST01 an entry from before the header";
  MakeOlder(legacy, 50);
  const CacheFolder folder(dir.string(), kFormat, nullptr);

  int age_minutes = 40;
  for (char key : {'a', 'b', 'c'}) {
    ASSERT_TRUE(folder.Store(Key(key), {&key, 1}).ok());
    MakeOlder(folder.PathOf(Key(key)), age_minutes -= 10);
  }

  for (const fs::path& user : users) EXPECT_TRUE(fs::exists(user)) << user;
  EXPECT_FALSE(fs::exists(legacy)) << "the oldest of four entries of the cache's own";
  for (char key : {'a', 'b', 'c'}) EXPECT_EQ(folder.Load(Key(key), AsIs), std::string(1, key));
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
