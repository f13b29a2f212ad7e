#include "host/sensors/tactile/field_map.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <random>

#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {
namespace {

// An 8 x 8 tile source keeps the test fast; its field is as smooth as the finer models'.
std::shared_ptr<const TiledFilmField> Source() {
  static const auto source = std::make_shared<const TiledFilmField>(FilmGeometry{}, 8);
  return source;
}

const FieldMapFilmField& Map() {
  static const FieldMapFilmField map(Source());
  return map;
}

TEST(FieldMapTest, ExactAtGridNodes) {
  // Setup
  const FieldMapGrid& grid = Map().grid();
  const Eigen::Vector3d spacing =
      (grid.box.max_m - grid.box.min_m)
          .cwiseQuotient((grid.nodes.array() - 1).matrix().cast<double>());
  for (const Eigen::Vector3i& node : {Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(3, 5, 2),
                                      Eigen::Vector3i(grid.nodes.x() - 1, 0, grid.nodes.z() - 1),
                                      Eigen::Vector3i(grid.nodes - Eigen::Vector3i::Ones())}) {
    FilmPose pose;
    pose.centre_m = grid.box.min_m + spacing.cwiseProduct(node.cast<double>());
    // Run
    const std::optional<Eigen::Vector3d> b = Map().Lookup(pose);
    // Check
    ASSERT_TRUE(b.has_value()) << node.transpose();
    const Eigen::Vector3d ref = Source()->FieldAtChip(pose);
    EXPECT_LT((*b - ref).norm(), 1e-12 * ref.norm()) << node.transpose();
  }
}

TEST(FieldMapTest, WithinOnePerMilleOfSourceBetweenNodes) {
  // Run: most of the 13 samples per axis fall between the 11 x 11 x 9 nodes.
  const double error = MaxRelativeError(Map(), *Source(), 13);
  // Check
  EXPECT_LT(error, 1e-3);
}

TEST(FieldMapTest, RandomPosesInWorkingVolumeAreWithinBound) {
  // Setup
  std::mt19937 rng(21);
  const FilmCentreBox box = FilmWorkingVolume();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    FilmPose pose;
    pose.centre_m =
        box.min_m + (box.max_m - box.min_m).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    // Run
    const Eigen::Vector3d b = Map().FieldAtChip(pose);
    // Check
    const Eigen::Vector3d ref = Source()->FieldAtChip(pose);
    EXPECT_LT((b - ref).norm(), 1e-3 * ref.norm()) << pose.centre_m.transpose();
  }
}

TEST(FieldMapTest, TiltedPoseUsesTheTurnedTable) {
  // Setup: a 5° tilt, still on the grid once turned into the film's axes.
  FilmPose pose;
  pose.centre_m = Eigen::Vector3d(0.001, -0.002, -0.0095);
  pose.orientation = Eigen::AngleAxisd(0.087, Eigen::Vector3d(0.3, 1.0, 0.2).normalized());
  // Run
  const std::optional<Eigen::Vector3d> b = Map().Lookup(pose);
  // Check
  ASSERT_TRUE(b.has_value());
  const Eigen::Vector3d ref = Source()->FieldAtChip(pose);
  EXPECT_LT((*b - ref).norm(), 1e-3 * ref.norm());
  EXPECT_GT((*b - Map().FieldAtChip(FilmPose{pose.centre_m, {}})).norm(), 1e-2 * ref.norm());
}

TEST(FieldMapTest, OffGridFallsBackToSource) {
  // Setup
  for (const Eigen::Vector3d& centre :
       {Eigen::Vector3d(0.0045, 0, -0.010), Eigen::Vector3d(0, -0.006, -0.010),
        Eigen::Vector3d(0, 0, -0.0065), Eigen::Vector3d(0, 0, -0.020)}) {
    FilmPose pose;
    pose.centre_m = centre;
    // Run
    const std::optional<Eigen::Vector3d> looked_up = Map().Lookup(pose);
    const Eigen::Vector3d b = Map().FieldAtChip(pose);
    // Check
    EXPECT_FALSE(looked_up.has_value()) << centre.transpose();
    EXPECT_EQ(b, Source()->FieldAtChip(pose)) << centre.transpose();
  }
}

TEST(FieldMapTest, MapFromItsOwnTableAnswersBitForBit) {
  const auto copy = FieldMapFilmField::FromTable(Source(), Map().grid(), Map().table());
  ASSERT_NE(copy, nullptr);
  EXPECT_EQ(Map().table().size(), FieldMapFilmField::StoredNodeCount(Map().grid()));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const FilmCentreBox box = FilmWorkingVolume();
  for (int i = 0; i < 20; ++i) {
    FilmPose pose;
    pose.centre_m =
        box.min_m +
        (box.max_m - box.min_m).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    EXPECT_EQ(copy->FieldAtChip(pose), Map().FieldAtChip(pose)) << pose.centre_m.transpose();
  }
}

TEST(FieldMapTest, TableOfTheWrongSizeOrWithANonFiniteValueIsRefused) {
  std::vector<Eigen::Vector3d> short_table = Map().table();
  short_table.pop_back();
  EXPECT_EQ(FieldMapFilmField::FromTable(Source(), Map().grid(), short_table), nullptr);
  std::vector<Eigen::Vector3d> with_nan = Map().table();
  with_nan[5].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(FieldMapFilmField::FromTable(Source(), Map().grid(), with_nan), nullptr);
  FieldMapGrid flat = Map().grid();
  flat.box.max_m.z() = flat.box.min_m.z();
  EXPECT_EQ(FieldMapFilmField::FromTable(Source(), flat, Map().table()), nullptr);
  EXPECT_EQ(FieldMapFilmField::FromTable(nullptr, Map().grid(), Map().table()), nullptr);
}

}  // namespace
}  // namespace hilrig::host
