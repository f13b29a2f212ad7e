#include "host/sensors/tactile/film_magnet.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "host/sensors/tactile/cuboid_field.h"

namespace hilrig::host {

Eigen::Vector3d FilmPolarizationDirection(const FilmGeometry& film, double x_m, double y_m) {
  const double in_plane = std::cos(film.out_of_plane_tilt_rad);
  const double normal = std::sin(film.out_of_plane_tilt_rad);
  switch (film.pattern) {
    case FilmGeometry::Pattern::kCentripetal: {
      const double r = std::hypot(x_m, y_m);
      if (r == 0.0) return Eigen::Vector3d(0.0, 0.0, normal);
      return Eigen::Vector3d(-in_plane * x_m / r, -in_plane * y_m / r, normal);
    }
  }
  std::abort();
}

TiledFilmField::TiledFilmField(const FilmGeometry& film, int tiles_per_side)
    : film_(film), tiles_per_side_(tiles_per_side) {
  if (tiles_per_side < 1 || !(film.side_m > 0.0) || !(film.thickness_m > 0.0)) {
    std::fprintf(stderr, "TiledFilmField: bad geometry or tile count %d\n", tiles_per_side);
    std::abort();
  }
  const double pitch = film.side_m / tiles_per_side;
  const int centre = tiles_per_side % 2 == 1 ? tiles_per_side / 2 : -1;
  tile_centres_m_.reserve(tiles_per_side * tiles_per_side + 3);
  tile_half_sizes_m_.reserve(tiles_per_side * tiles_per_side + 3);
  tile_polarizations_t_.reserve(tiles_per_side * tiles_per_side + 3);
  for (int i = 0; i < tiles_per_side; ++i) {
    for (int j = 0; j < tiles_per_side; ++j) {
      const double x = -film.side_m / 2.0 + (i + 0.5) * pitch;
      const double y = -film.side_m / 2.0 + (j + 0.5) * pitch;
      if (i != centre || j != centre) {
        AddTile(x, y, pitch);
        continue;
      }
      // The pattern has no in-plane direction at the film centre, and its mean over a tile
      // centred there is zero: one uniform tile would leave the middle of the film unpolarized
      // (tiles:1 a zero field, tiles:3 less accurate than tiles:2). Four quarter tiles, each
      // polarized at its own centre, keep the error falling with every added tile per side.
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
          AddTile(x + (a - 0.5) * pitch / 2.0, y + (b - 0.5) * pitch / 2.0, pitch / 2.0);
        }
      }
    }
  }
}

void TiledFilmField::AddTile(double x_m, double y_m, double side_m) {
  tile_centres_m_.emplace_back(x_m, y_m, 0.0);
  tile_half_sizes_m_.emplace_back(side_m / 2.0, side_m / 2.0, film_.thickness_m / 2.0);
  tile_polarizations_t_.push_back(film_.polarization_t *
                                  FilmPolarizationDirection(film_, x_m, y_m));
}

Eigen::Vector3d TiledFilmField::FieldInFilmFrame(const Eigen::Vector3d& point_m) const {
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < tile_centres_m_.size(); ++i) {
    // A point on a tile edge (only possible inside the film) contributes nothing; the chip never
    // gets there, so the flag is not propagated.
    b += CuboidField(tile_half_sizes_m_[i], tile_polarizations_t_[i], point_m - tile_centres_m_[i])
             .field_t;
  }
  return b;
}

Eigen::Vector3d TiledFilmField::FieldAtChip(const FilmPose& pose) const {
  // The chip sits at the origin of the chip frame; in the film frame that is -Rᵀ c.
  const Eigen::Matrix3d rotation = pose.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d chip_in_film = -(rotation.transpose() * pose.centre_m);
  return rotation * FieldInFilmFrame(chip_in_film);
}

}  // namespace hilrig::host
