#include "host/cache/field_map_store.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

std::vector<Eigen::Vector3d> ThreeNodes() {
  return {Eigen::Vector3d(1e-3, -2e-3, 3e-17), Eigen::Vector3d::Zero(),
          Eigen::Vector3d(-0.0, std::numeric_limits<double>::denorm_min(), 4.5e-5)};
}

// The smallest grid (2 nodes per axis, 4^3 stored) and a table of its size.
FieldMapGrid SmallGrid() {
  FieldMapGrid grid;
  grid.nodes = Eigen::Vector3i(2, 2, 2);
  return grid;
}
std::vector<Eigen::Vector3d> SmallTable() {
  std::vector<Eigen::Vector3d> table;
  for (int i = 0; i < 64; ++i) table.emplace_back(1e-3 * i, -2e-3, 0.25 + i);
  return table;
}

TEST(FieldMapStoreTest, ATableReadsBackBitForBit) {
  const auto parsed = ParseFieldMapTable(SerializeFieldMapTable(ThreeNodes()));
  ASSERT_TRUE(parsed);
  const std::vector<Eigen::Vector3d>& table = parsed.value();
  ASSERT_EQ(table.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(std::signbit(table[i][axis]), std::signbit(ThreeNodes()[i][axis]));
      EXPECT_EQ(table[i][axis], ThreeNodes()[i][axis]);
    }
  }
}

TEST(FieldMapStoreTest, TruncatedForeignOrPaddedBytesAreAMiss) {
  const std::string bytes = SerializeFieldMapTable(ThreeNodes());
  EXPECT_FALSE(ParseFieldMapTable(bytes.substr(0, bytes.size() - 1)));
  EXPECT_FALSE(ParseFieldMapTable(bytes + "x"));
  EXPECT_FALSE(ParseFieldMapTable(""));
  std::string huge_count = bytes;
  huge_count[7] = '\x7f';  // the count's high byte
  EXPECT_FALSE(ParseFieldMapTable(huge_count));
}

TEST(FieldMapStoreTest, TheKeyChangesWithLevelGridAndCode) {
  const FilmFidelity opmap{true, 32, true};
  const FieldMapGrid grid;
  const std::string key = FieldMapCacheKey(opmap, grid, "code-a");
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(key, FieldMapCacheKey(opmap, grid, "code-a"));
  EXPECT_NE(key, FieldMapCacheKey(opmap, grid, "code-b"));
  EXPECT_NE(key, FieldMapCacheKey({true, 32, false}, grid, "code-a"));
  EXPECT_NE(key, FieldMapCacheKey({true, 16, true}, grid, "code-a"));
  FieldMapGrid finer = grid;
  finer.nodes.z() += 1;
  EXPECT_NE(key, FieldMapCacheKey(opmap, finer, "code-a"));
  FieldMapGrid moved = grid;
  moved.box.min_m.x() -= 1e-9;
  EXPECT_NE(key, FieldMapCacheKey(opmap, moved, "code-a"));
}

TEST(FieldMapStoreTest, StoreThenLoadAndMissesForOtherCodeOrDamagedFiles) {
  const std::string dir = ::testing::TempDir() + "/field_map_store_test";
  std::filesystem::remove_all(dir);
  const FilmFidelity level{true, 4, false};
  const FieldMapGrid grid = SmallGrid();
  const FileFieldMapStore store(dir + "/nested", "code-a", nullptr);

  EXPECT_FALSE(store.Load(level, grid).has_value());
  store.Store(level, grid, SmallTable());
  const auto loaded = store.Load(level, grid);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(*loaded, SmallTable());
  EXPECT_FALSE(FileFieldMapStore(dir + "/nested", "code-b", nullptr).Load(level, grid));
  std::ofstream(store.PathOf(level, grid), std::ios::trunc) << "garbage";
  EXPECT_FALSE(store.Load(level, grid).has_value());
  std::filesystem::remove_all(dir);
}

TEST(FieldMapStoreTest, AStoreThatFailsIsSaidAndCostsNothingElse) {
  std::ostringstream notes;
  const FileFieldMapStore store(UncreatableFolder("field_map_store_").string(), "code-a", &notes);

  store.Store({true, 4, true}, FieldMapGrid{}, ThreeNodes());
  EXPECT_NE(notes.str().find("the opmap:4 field map is not kept for later runs"), std::string::npos)
      << notes.str();
  EXPECT_FALSE(store.Load({true, 4, true}, FieldMapGrid{}).has_value());
}

// One byte changed anywhere in the values is a miss (it used to be read as a slightly different
// field), and so is a whole table that does not fit the grid or holds a non-finite value.
TEST(FieldMapStoreTest, AChangedByteOrATableThatDoesNotFitTheGridIsAMissAndIsSaid) {
  const fs::path dir = FreshTestDir("field_map_store_");
  std::ostringstream notes;
  const FilmFidelity level{true, 4, false};
  const FileFieldMapStore store(dir.string(), "code-a", &notes);
  const std::string path = store.PathOf(level, SmallGrid());

  store.Store(level, SmallGrid(), SmallTable());
  ChangeByteFromEnd(path, 20, 0x01);  // one bit of the last node's x, far below its size
  EXPECT_FALSE(store.Load(level, SmallGrid()).has_value());
  EXPECT_NE(notes.str().find(path + ": the checksum does not match"), std::string::npos)
      << notes.str();

  store.Store(level, SmallGrid(), ThreeNodes());
  EXPECT_FALSE(store.Load(level, SmallGrid()).has_value());
  EXPECT_NE(notes.str().find("3 nodes, the grid stores 64"), std::string::npos) << notes.str();

  std::vector<Eigen::Vector3d> infinite = SmallTable();
  infinite[5].y() = std::numeric_limits<double>::infinity();
  store.Store(level, SmallGrid(), infinite);
  EXPECT_FALSE(store.Load(level, SmallGrid()).has_value());
  EXPECT_NE(notes.str().find("node 5 is not finite"), std::string::npos) << notes.str();

  store.Store(level, SmallGrid(), SmallTable());
  EXPECT_EQ(store.Load(level, SmallGrid()), SmallTable());
}

// A folder at the entry path is a miss, and a store over it is said; neither throws.
TEST(FieldMapStoreTest, AFolderAtTheEntryPathIsAMissAndAStoreOverItIsSaid) {
  const fs::path dir = FreshTestDir("field_map_store_");
  std::ostringstream notes;
  const FilmFidelity level{true, 4, false};
  const FileFieldMapStore store(dir.string(), "code-a", &notes);
  fs::create_directories(store.PathOf(level, SmallGrid()));

  EXPECT_FALSE(store.Load(level, SmallGrid()).has_value());
  store.Store(level, SmallGrid(), SmallTable());
  EXPECT_NE(notes.str().find("a folder, not a regular file"), std::string::npos) << notes.str();
  EXPECT_NE(notes.str().find("the map:4 field map is not kept for later runs"), std::string::npos);
}

// The folder may hold files of the user's: more *.map files than the bound, a file named like an
// entry that the cache did not write, a temporary name not of an entry. A store removes none of
// them (it used to remove every *.map file past the 64 most recent).
TEST(FieldMapStoreTest, AStoreLeavesFilesTheCacheDidNotWrite) {
  const fs::path dir = FreshTestDir("field_map_store_");
  const std::vector<fs::path> users = PlantUserFiles(dir, ".map", 100);
  const FileFieldMapStore store(dir.string(), "code-a", nullptr);

  store.Store({true, 4, false}, SmallGrid(), SmallTable());

  for (const fs::path& user : users) EXPECT_TRUE(fs::exists(user)) << user;
  EXPECT_TRUE(store.Load({true, 4, false}, SmallGrid()).has_value());
}

}  // namespace
}  // namespace hilrig::host
