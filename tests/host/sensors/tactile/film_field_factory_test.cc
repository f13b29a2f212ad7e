// Fidelity names and the process-wide sharing of the built models.
#include "host/sensors/tactile/film_field_factory.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {
namespace {

TEST(FilmFidelityTest, ParsesEveryLevelName) {
  const FilmFidelity tiles = ParseFilmFidelity("tiles:8").value();
  EXPECT_FALSE(tiles.field_map);
  EXPECT_EQ(tiles.tiles_per_side, 8);
  const FilmFidelity map = ParseFilmFidelity("map").value();
  EXPECT_TRUE(map.field_map);
  EXPECT_FALSE(map.operating_volume);
  EXPECT_EQ(map.tiles_per_side, 32);
  const FilmFidelity opmap = ParseFilmFidelity("opmap:4").value();
  EXPECT_TRUE(opmap.field_map);
  EXPECT_TRUE(opmap.operating_volume);
  EXPECT_EQ(opmap.tiles_per_side, 4);
}

TEST(FilmFidelityTest, RefusesBadNames) {
  for (const char* bad : {"", "tiles", "tiles:0", "tiles:129", "tiles:2.5", "map:", "mesh:4"}) {
    EXPECT_FALSE(ParseFilmFidelity(bad).ok()) << bad;
    EXPECT_FALSE(MakeFilmField(bad).ok()) << bad;
  }
}

// Tabulating a map takes a second or more (24 s for map:128); a stop request ends it, and the
// unfinished map is not kept for the next caller.
TEST(MakeFilmFieldTest, AStopRequestEndsATabulationAndKeepsNothing) {
  const std::atomic<bool> stop_requested{true};
  const auto stopped = MakeFilmField("map:3", nullptr, &stop_requested);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().message, "interrupted while tabulating the map:3 field map");
  EXPECT_EQ(stopped.error().code, rig::ErrorCode::kInterrupted);
  const auto built = MakeFilmField("map:3");
  ASSERT_TRUE(built.ok());
  EXPECT_TRUE(built.value()->FieldAtChip(FilmPose{}).allFinite());
}

TEST(FilmFieldModelsTest, OneLevelIsBuiltOnceAndShared) {
  FilmFieldModels models;
  const auto first = models.Get("map:2").value();
  const auto again = models.Get("map:2").value();
  EXPECT_EQ(first.get(), again.get());
  EXPECT_NE(models.Get("opmap:2").value().get(), first.get());
  EXPECT_NE(models.Get("tiles:2").value().get(), first.get());
  EXPECT_EQ(models.Get("map").value().get(), models.Get("map:32").value().get());
  EXPECT_FALSE(models.Get("mesh:4").ok());
}

// Nothing is shared outside an owner: another owner, or MakeFilmField, builds its own.
TEST(FilmFieldModelsTest, OwnersShareNothing) {
  FilmFieldModels one;
  FilmFieldModels other;
  const auto mine = one.Get("tiles:2").value();
  EXPECT_NE(other.Get("tiles:2").value().get(), mine.get());
  EXPECT_NE(MakeFilmField("tiles:2").value().get(), mine.get());
}

TEST(FilmFieldModelsTest, AStoppedBuildKeepsNothing) {
  FilmFieldModels models;
  const std::atomic<bool> stop_requested{true};
  const auto stopped = models.Get("map:3", &stop_requested);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().code, rig::ErrorCode::kInterrupted);
  const auto built = models.Get("map:3");
  ASSERT_TRUE(built.ok());
  EXPECT_TRUE(built.value()->FieldAtChip(FilmPose{}).allFinite());
}

// Threads asking for one level get one model; a level being tabulated does not hold back another.
TEST(FilmFieldModelsTest, ThreadsAskingForOneLevelShareOneModel) {
  FilmFieldModels models;
  std::vector<std::shared_ptr<const FilmFieldModel>> got(4);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&, i] { got[i] = models.Get(i % 2 == 0 ? "map:4" : "tiles:5").value(); });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(got[0].get(), got[2].get());
  EXPECT_EQ(got[1].get(), got[3].get());
  EXPECT_NE(got[0].get(), got[1].get());
}

TEST(MakeFilmFieldTest, SharedModelAnswersLikeAFreshOne) {
  const FilmPose pose{Eigen::Vector3d(0.0005, -0.0003, -0.0095), Eigen::Quaterniond::Identity()};
  const Eigen::Vector3d shared_t = MakeFilmField("tiles:3").value()->FieldAtChip(pose);
  const Eigen::Vector3d fresh_t = TiledFilmField(FilmGeometry{}, 3).FieldAtChip(pose);
  EXPECT_EQ(shared_t, fresh_t);
  EXPECT_GT(fresh_t.norm(), 0.0);
}

// A store in memory: it answers what it was given and records what it was handed.
class FakeFieldMapStore final : public FieldMapTableStore {
 public:
  std::optional<std::vector<Eigen::Vector3d>> Load(const FilmFidelity& level,
                                                   const FieldMapGrid&) const override {
    ++loads;
    if (!answer || FilmFidelityName(level) != answer_level) return std::nullopt;
    return answer;
  }
  void Store(const FilmFidelity& level, const FieldMapGrid& grid,
             const std::vector<Eigen::Vector3d>& table) const override {
    stored_level = FilmFidelityName(level);
    stored_nodes = FieldMapFilmField::StoredNodeCount(grid);
    stored = table;
  }

  std::string answer_level;
  std::optional<std::vector<Eigen::Vector3d>> answer;
  mutable int loads = 0;
  mutable std::string stored_level;
  mutable std::size_t stored_nodes = 0;
  mutable std::vector<Eigen::Vector3d> stored;
};

TEST(MakeFilmFieldTest, MapLevelTheStoreLacksIsTabulatedAndHandedToIt) {
  const FakeFieldMapStore store;
  const auto model = MakeFilmField("map:5", &store).value();

  EXPECT_EQ(store.loads, 1);
  EXPECT_EQ(store.stored_level, "map:5");
  ASSERT_EQ(store.stored.size(), store.stored_nodes);
  const auto& map = dynamic_cast<const FieldMapFilmField&>(*model);
  EXPECT_EQ(store.stored, map.table());
  const FilmPose pose;
  EXPECT_EQ(
      model->FieldAtChip(pose),
      FieldMapFilmField(std::make_shared<TiledFilmField>(FilmGeometry{}, 5)).FieldAtChip(pose));
}

TEST(MakeFilmFieldTest, MapLevelTheStoreHasIsReadNotTabulated) {
  FakeFieldMapStore store;
  store.answer_level = "opmap:3";
  // A uniform field no film makes: only a map read from the store can answer it.
  const Eigen::Vector3d uniform_t(1e-3, -2e-3, 3e-3);
  store.answer = std::vector<Eigen::Vector3d>(
      FieldMapFilmField::StoredNodeCount(OperatingVolumeMapGrid()), uniform_t);
  const auto model = MakeFilmField("opmap:3", &store).value();

  EXPECT_TRUE(store.stored.empty()) << "nothing was tabulated";
  const FilmPose rest;  // the rest pose lies inside the operating volume
  EXPECT_LT((model->FieldAtChip(rest) - uniform_t).norm(), 1e-15);
}

TEST(MakeFilmFieldTest, TableThatDoesNotFitTheGridIsTabulatedAgain) {
  FakeFieldMapStore store;
  store.answer_level = "opmap:1";
  store.answer = std::vector<Eigen::Vector3d>(3, Eigen::Vector3d::Zero());
  const auto model = MakeFilmField("opmap:1", &store).value();

  EXPECT_EQ(store.stored_level, "opmap:1");
  EXPECT_EQ(store.stored.size(), FieldMapFilmField::StoredNodeCount(OperatingVolumeMapGrid()));
  EXPECT_GT(model->FieldAtChip(FilmPose{}).norm(), 0.0);
}

// An owner asks its store once per level, whatever else in the process built that level before.
TEST(FilmFieldModelsTest, EachOwnerAsksItsOwnStoreOncePerLevel) {
  ASSERT_TRUE(MakeFilmField("map:6").ok());
  const FakeFieldMapStore store;
  FilmFieldModels models(&store);
  ASSERT_TRUE(models.Get("map:6").ok());
  ASSERT_TRUE(models.Get("map:6").ok());
  EXPECT_EQ(store.loads, 1);
  EXPECT_EQ(store.stored_level, "map:6");
}

TEST(FilmFidelityTest, CanonicalNames) {
  EXPECT_EQ(FilmFidelityName(ParseFilmFidelity("map").value()), "map:32");
  EXPECT_EQ(FilmFidelityName(ParseFilmFidelity("opmap:4").value()), "opmap:4");
  EXPECT_EQ(FilmFidelityName(ParseFilmFidelity("tiles:16").value()), "tiles:16");
}

}  // namespace
}  // namespace hilrig::host
