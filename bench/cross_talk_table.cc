// Prints how far the six films' fields reach (host/sensors/tactile/film_cross_talk.h): the other
// five films' field at a chip, and the six films' field at the reference magnetometer at several
// heights above the frame centre, with the frame open and closed to several object radii (films at
// rest). The reference must sit where the second stays small against what the compensation
// corrects. Usage: hilrig_cross_talk_table [level], level a tile level (default tiles:16).
#include <cstdio>
#include <string>

#include "host/plant/gripper_frame.h"
#include "host/sensors/tactile/film_cross_talk.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace {

using hilrig::host::ChipPositionBody;
using hilrig::host::FilmCrossTalk;
using hilrig::host::FilmPose;
using hilrig::host::GripperFrameParams;
using hilrig::host::kTactileSensorCount;
using hilrig::host::TactileSensorParams;

constexpr double kHeightsM[] = {0.02, 0.05, 0.08, 0.10, 0.15, 0.20};
constexpr double kFilmRadiiM[] = {0.055, 0.045, 0.040, 0.032, 0.025};

}  // namespace

int main(int argc, char** argv) {
  const std::string level = argc > 1 ? argv[1] : "tiles:16";
  auto film = hilrig::host::MakeFilmField(level);
  if (!film.ok()) {
    std::fprintf(stderr, "hilrig_cross_talk_table: %s\n", film.error().message.c_str());
    return 2;
  }
  const auto tactile = hilrig::host::DefaultTactileLayout();
  const GripperFrameParams frame;
  std::array<FilmPose, kTactileSensorCount> rest;
  rest.fill(FilmPose{});
  std::printf("films' field (uT) from %s; chip: the other five at one chip, along its normal\n",
              level.c_str());
  std::printf("| film radius (mm) | chip |");
  for (double h : kHeightsM) std::printf(" reference at %.0f mm |", h * 1e3);
  std::printf("\n|---|---|");
  for (std::size_t k = 0; k < std::size(kHeightsM); ++k) std::printf("---|");
  std::printf("\n");
  for (double radius_m : kFilmRadiiM) {
    std::array<Eigen::Vector3d, kTactileSensorCount> chips;
    const double angle_rad = hilrig::host::AngleForPadRadius(frame, radius_m);
    for (int i = 0; i < kTactileSensorCount; ++i) chips[i] = ChipPositionBody(frame, i, angle_rad);
    std::printf("| %.0f |", radius_m * 1e3);
    for (std::size_t k = 0; k <= std::size(kHeightsM); ++k) {
      TactileSensorParams reference = hilrig::host::DefaultReferenceSensor();
      reference.position_body_m = {0, 0, k > 0 ? kHeightsM[k - 1] : 0.15};
      FilmCrossTalk cross_talk(film.value(), tactile, reference);
      cross_talk.Update(chips, rest);
      const double value_t =
          k == 0 ? cross_talk.AtTactileSensor(0).z() : cross_talk.AtReferenceSensor().norm();
      std::printf(" %.2f |", value_t * 1e6);
    }
    std::printf("\n");
  }
  return 0;
}
