#include "host/sensors/tactile/dipole_film_field.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <utility>

namespace hilrig::host {
namespace {
constexpr double kMu0 = 4e-7 * std::numbers::pi;  // close enough to CODATA for a fake
// Sub-samples per cell side when integrating the pattern into a cell moment.
constexpr int kSamplesPerCell = 32;
}  // namespace

Eigen::Vector3d PointDipoleField(const Eigen::Vector3d& moment_a_m2,
                                 const Eigen::Vector3d& offset_m) {
  const double r2 = offset_m.squaredNorm();
  if (r2 == 0.0) return Eigen::Vector3d::Zero();
  const double r = std::sqrt(r2);
  const double r5 = r2 * r2 * r;
  return kMu0 / (4.0 * std::numbers::pi) *
         (3.0 * moment_a_m2.dot(offset_m) * offset_m - r2 * moment_a_m2) / r5;
}

DipoleFilmField::DipoleFilmField(std::vector<PointDipole> dipoles) : dipoles_(std::move(dipoles)) {}

DipoleFilmField DipoleFilmField::FromFilm(const FilmGeometry& film, int dipoles_per_side) {
  if (dipoles_per_side < 1) {
    std::fprintf(stderr, "DipoleFilmField: dipoles_per_side must be >= 1\n");
    std::abort();
  }
  const double cell = film.side_m / dipoles_per_side;
  const double sub = cell / kSamplesPerCell;
  const double sub_volume = sub * sub * film.thickness_m;
  std::vector<PointDipole> dipoles;
  for (int i = 0; i < dipoles_per_side; ++i) {
    for (int j = 0; j < dipoles_per_side; ++j) {
      PointDipole d;
      d.position_m = Eigen::Vector3d(-film.side_m / 2.0 + (i + 0.5) * cell,
                                     -film.side_m / 2.0 + (j + 0.5) * cell, 0.0);
      for (int a = 0; a < kSamplesPerCell; ++a) {
        for (int b = 0; b < kSamplesPerCell; ++b) {
          const double x = d.position_m.x() - cell / 2.0 + (a + 0.5) * sub;
          const double y = d.position_m.y() - cell / 2.0 + (b + 0.5) * sub;
          d.moment_a_m2 +=
              film.polarization_t / kMu0 * sub_volume * FilmPolarizationDirection(film, x, y);
        }
      }
      dipoles.push_back(d);
    }
  }
  return DipoleFilmField(std::move(dipoles));
}

Eigen::Vector3d DipoleFilmField::FieldAtChip(const FilmPose& pose) const {
  const Eigen::Matrix3d rotation = pose.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d chip_in_film = -(rotation.transpose() * pose.centre_m);
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const PointDipole& d : dipoles_) {
    b += PointDipoleField(d.moment_a_m2, chip_in_film - d.position_m);
  }
  return rotation * b;
}

}  // namespace hilrig::host
