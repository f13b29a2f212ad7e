#include "host/bench/field_map_store.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

std::vector<Eigen::Vector3d> ThreeNodes() {
  return {Eigen::Vector3d(1e-3, -2e-3, 3e-17), Eigen::Vector3d::Zero(),
          Eigen::Vector3d(-0.0, std::numeric_limits<double>::denorm_min(), 4.5e-5)};
}

TEST(FieldMapStoreTest, ATableReadsBackBitForBit) {
  const auto parsed = ParseFieldMapTable(SerializeFieldMapTable(ThreeNodes()));
  ASSERT_TRUE(parsed.has_value());
  ASSERT_EQ(parsed->size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(std::signbit((*parsed)[i][axis]), std::signbit(ThreeNodes()[i][axis]));
      EXPECT_EQ((*parsed)[i][axis], ThreeNodes()[i][axis]);
    }
  }
}

TEST(FieldMapStoreTest, TruncatedForeignOrPaddedBytesAreAMiss) {
  const std::string bytes = SerializeFieldMapTable(ThreeNodes());
  EXPECT_FALSE(ParseFieldMapTable(bytes.substr(0, bytes.size() - 1)).has_value());
  EXPECT_FALSE(ParseFieldMapTable(bytes + "x").has_value());
  EXPECT_FALSE(ParseFieldMapTable("").has_value());
  std::string foreign = bytes;
  foreign[0] = 'X';
  EXPECT_FALSE(ParseFieldMapTable(foreign).has_value());
  std::string huge_count = bytes;
  huge_count[15] = '\x7f';  // the count's high byte
  EXPECT_FALSE(ParseFieldMapTable(huge_count).has_value());
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
  const FieldMapGrid grid;
  const FileFieldMapStore store(dir + "/nested", "code-a", nullptr);

  EXPECT_FALSE(store.Load(level, grid).has_value());
  store.Store(level, grid, ThreeNodes());
  const auto loaded = store.Load(level, grid);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(*loaded, ThreeNodes());
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

}  // namespace
}  // namespace hilrig::host
