// The magnetized film on top of a tactile sensor's silicone block, and its highest-fidelity field
// model: the film cut into N x N cuboid tiles, each uniformly polarized along the film's pattern at
// the tile centre, summed with the closed-form cuboid field (cuboid_field.h). An odd grid's centre
// tile, where the pattern has no direction, is cut into four quarter tiles.
//
// "Centripetally magnetized" is read here as an in-plane polarization pointing at the film centre
// from every point, J(x, y) = -J r̂: the magnetic analogue of a radial Halbach ring. Its volume
// charge -div M = M / r piles up at the centre (balanced by a negative rim charge), so on the axis
// the film acts like a single north pole: B points away from the film on both sides and is
// radially symmetric, which is what makes the field at the chip move smoothly with shear (Bx, By)
// and with compression (Bz). Printed magnetized films are often not perfectly in-plane; an optional
// tilt of the polarization out of the plane (towards +z of the film) models that.
//
// Geometry chosen: an 18 mm square (it fits on the 20 mm silicone top with a 1 mm rim for the
// mould wall), 1 mm thick, J = 0.2 T (a bonded NdFeB/elastomer composite, about a sixth of
// sintered NdFeB). That gives Bz = 3.58 mT at rest (film centre 10 mm below the chip), 6.0 mT at
// 8 mm and 2.2 mT at 12 mm; over the working volume (x, y in ±3 mm) Bz spans 1.7-6.0 mT and |Bx|
// stays under 2.2 mT, so the MLX90393 at its highest gain (about ±4.9 mT in x, y and ±7.9 mT in z)
// does not saturate at rest or in the working volume: the design's "a few mT at 8-12 mm".
#pragma once

#include <Eigen/Core>
#include <vector>

#include "host/sensors/tactile/film_field.h"

namespace hilrig::host {

struct FilmGeometry {
  enum class Pattern {
    kCentripetal,  // in-plane, towards the film centre (plus the optional out-of-plane tilt)
  };
  double side_m = 0.018;
  double thickness_m = 0.001;
  double polarization_t = 0.2;
  Pattern pattern = Pattern::kCentripetal;
  // Tilt of the polarization out of the film plane, towards the film's +z; 0 = purely in-plane.
  double out_of_plane_tilt_rad = 0.0;
};

// Direction (unit vector, film frame) of the polarization at (x, y) of the film. At the exact
// centre the in-plane direction is undefined; there only the out-of-plane part remains.
Eigen::Vector3d FilmPolarizationDirection(const FilmGeometry& film, double x_m, double y_m);

class TiledFilmField final : public FilmFieldModel {
 public:
  // tiles_per_side >= 1; the film frame has its origin at the centre of the film's volume. An odd
  // count sums N^2 + 3 cuboids (the centre tile in quarters), an even one N^2.
  TiledFilmField(const FilmGeometry& film, int tiles_per_side);

  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override;

  // B at a point given in the film frame, in film axes.
  Eigen::Vector3d FieldInFilmFrame(const Eigen::Vector3d& point_m) const;

  const FilmGeometry& geometry() const { return film_; }
  int tiles_per_side() const { return tiles_per_side_; }

 private:
  // One uniformly polarized cuboid of side side_m, centred at (x, y) in the film's mid-plane.
  void AddTile(double x_m, double y_m, double side_m);

  FilmGeometry film_;
  int tiles_per_side_;
  std::vector<Eigen::Vector3d> tile_centres_m_;
  std::vector<Eigen::Vector3d> tile_half_sizes_m_;
  std::vector<Eigen::Vector3d> tile_polarizations_t_;
};

}  // namespace hilrig::host
