// Fidelity names and the process-wide sharing of the built models.
#include "host/sensors/tactile/film_field_factory.h"

#include <gtest/gtest.h>

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

TEST(MakeFilmFieldTest, OneLevelIsBuiltOnceAndShared) {
  const auto first = MakeFilmField("map:2").value();
  const auto again = MakeFilmField("map:2").value();
  EXPECT_EQ(first.get(), again.get());
  EXPECT_NE(MakeFilmField("opmap:2").value().get(), first.get());
  EXPECT_NE(MakeFilmField("tiles:2").value().get(), first.get());
  EXPECT_EQ(MakeFilmField("map").value().get(), MakeFilmField("map:32").value().get());
}

TEST(MakeFilmFieldTest, SharedModelAnswersLikeAFreshOne) {
  const FilmPose pose{Eigen::Vector3d(0.0005, -0.0003, -0.0095), Eigen::Quaterniond::Identity()};
  const Eigen::Vector3d shared_t = MakeFilmField("tiles:3").value()->FieldAtChip(pose);
  const Eigen::Vector3d fresh_t = TiledFilmField(FilmGeometry{}, 3).FieldAtChip(pose);
  EXPECT_EQ(shared_t, fresh_t);
  EXPECT_GT(fresh_t.norm(), 0.0);
}

}  // namespace
}  // namespace hilrig::host
