#include "host/sensors/tactile/film_cross_talk.h"

#include <utility>

#include "host/sensors/tactile/dipole_film_field.h"
#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {
namespace {

bool SamePose(const FilmPose& a, const FilmPose& b) {
  return a.centre_m == b.centre_m && a.orientation.coeffs() == b.orientation.coeffs();
}

}  // namespace

std::shared_ptr<const FilmFieldModel> MakeCrossTalkFarField() {
  return std::make_shared<const DipoleFilmField>(
      DipoleFilmField::FromFilm(FilmGeometry{}, kCrossTalkDipolesPerSide));
}

FilmCrossTalk::FilmCrossTalk(std::shared_ptr<const FilmFieldModel> far_field,
                             const std::array<TactileSensorParams, kTactileSensorCount>& tactile,
                             const TactileSensorParams& reference)
    : far_field_(std::move(far_field)),
      reference_from_body_(reference.mounting_body_from_sensor.toRotationMatrix().transpose()),
      reference_position_body_m_(reference.position_body_m) {
  for (int i = 0; i < kTactileSensorCount; ++i) {
    body_from_sensor_[i] = tactile[i].mounting_body_from_sensor.toRotationMatrix();
    at_tactile_t_[i].setZero();
    chip_position_body_m_[i].setZero();
  }
}

Eigen::Vector3d FilmCrossTalk::FilmFieldAtBody(int film,
                                               const Eigen::Vector3d& point_body_m) const {
  const Eigen::Matrix3d& body_from_sensor = body_from_sensor_[film];
  const FilmPose& own = film_pose_[film];
  const Eigen::Vector3d film_body_m = chip_position_body_m_[film] + body_from_sensor * own.centre_m;
  // A chip at the point, with film i's chip axes: the film's pose relative to it.
  FilmPose relative;
  relative.centre_m = body_from_sensor.transpose() * (film_body_m - point_body_m);
  relative.orientation = own.orientation;
  return body_from_sensor * far_field_->FieldAtChip(relative);
}

void FilmCrossTalk::Update(
    const std::array<Eigen::Vector3d, kTactileSensorCount>& chip_position_body_m,
    const std::array<FilmPose, kTactileSensorCount>& film_pose) {
  bool moved = !computed_;
  for (int i = 0; i < kTactileSensorCount && !moved; ++i) {
    moved = chip_position_body_m[i] != chip_position_body_m_[i] ||
            !SamePose(film_pose[i], film_pose_[i]);
  }
  if (!moved) return;
  chip_position_body_m_ = chip_position_body_m;
  film_pose_ = film_pose;
  Eigen::Vector3d at_reference_body = Eigen::Vector3d::Zero();
  for (int j = 0; j < kTactileSensorCount; ++j) {
    Eigen::Vector3d at_chip_body = Eigen::Vector3d::Zero();
    for (int i = 0; i < kTactileSensorCount; ++i) {
      if (i != j) at_chip_body += FilmFieldAtBody(i, chip_position_body_m_[j]);
    }
    at_tactile_t_[j] = body_from_sensor_[j].transpose() * at_chip_body;
    at_reference_body += FilmFieldAtBody(j, reference_position_body_m_);
  }
  at_reference_t_ = reference_from_body_ * at_reference_body;
  computed_ = true;
  ++recomputations_;
}

}  // namespace hilrig::host
