// A cheap stand-in for the film's field, for tests of the parts around it (silicone, MLX90393,
// decoding, calibration jigs): the film as a few point dipoles. It is a fake, not a fidelity level:
// a centripetal film has (almost) no net dipole moment, so a single dipole would see nothing, and
// even the default 2 x 2 dipoles (one per quadrant, carrying that quadrant's moment) are off by
// tens of percent at the chip. It does have the right symmetry and signs (Bz > 0 above the centre,
// Bx = By = 0 there, B pointing away from the film centre), costs a few tens of nanoseconds,
// and is smooth everywhere away from the dipoles. Far from the film, with finer cells, it is a
// model: at 8 x 8 cells it is the films' field at the other chips and at the reference
// (film_cross_talk.h), within 1.2 % of fine tiles there.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {

struct PointDipole {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // film frame
  Eigen::Vector3d moment_a_m2 = Eigen::Vector3d::Zero();
};

// Flux density in tesla of a point dipole at offset_m from it (zero at the dipole itself).
Eigen::Vector3d PointDipoleField(const Eigen::Vector3d& moment_a_m2,
                                 const Eigen::Vector3d& offset_m);

class DipoleFilmField final : public FilmFieldModel {
 public:
  explicit DipoleFilmField(std::vector<PointDipole> dipoles);

  // dipoles_per_side^2 dipoles at the centres of equal square cells of the film, each with the
  // cell's total moment (the pattern integrated over the cell).
  static DipoleFilmField FromFilm(const FilmGeometry& film, int dipoles_per_side = 2);

  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override;

  const std::vector<PointDipole>& dipoles() const { return dipoles_; }

 private:
  std::vector<PointDipole> dipoles_;
};

}  // namespace hilrig::host
