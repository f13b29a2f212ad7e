// The films' fields away from their own chips: every film's field at the other five tactile chips
// and at the reference magnetometer. A film's field falls off fast but not to nothing: with the
// frame open the other five put about 3.5 uT on each chip, closed on a bottle about 11 uT, and at
// 20 mm above the frame centre the six give 30 uT (open) to 200 uT (closed), several times Earth's
// field, which the geomagnetic compensation would then subtract from every pad. The reference
// must sit far enough from the ring (docs/tactile.md gives the figures).
//
// The field of film i at a point q is its field at a chip placed at q with chip i's axes: the
// film model (film_field.h) answers for any film pose relative to a chip, so a model that is valid
// far from the film (cell dipoles, not a map of the pad's own working volume) computes it. With
// chip positions p_k and film poses (c_k, R_k) in each chip's frame S_k (mounting R_BS_k):
//
//   film i in the body:   f_i = p_i + R_BS_i c_i
//   at chip j (i != j):   B_j += R_BS_j^T R_BS_i F(pose(R_BS_i^T (f_i - p_j), R_k))
//   at the reference r:   B_r += R_BS_r^T R_BS_i F(pose(R_BS_i^T (f_i - p_r), R_k))
//
// Update recomputes only when a chip position or a film pose differs bit for bit from the last
// call: a frame at rest with its pads unloaded costs one evaluation per run.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>

#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/sensor_layout.h"

namespace hilrig::host {

// The films' fields away from their chips come from each film as kCrossTalkDipolesPerSide^2 point
// dipoles, each carrying its cell's moment (dipole_film_field.h): within 1.2 % of 32 x 32 tiles at
// the chips of an open to a closed frame and at the reference, where 4 x 4 tiles are off by up to
// 2.2 %, at a tenth of their cost (about 0.8 against 8.4 us per evaluation). Near its own chip a
// film needs tiles; 40 mm and more away the cells are small enough.
inline constexpr int kCrossTalkDipolesPerSide = 8;

// The far-field model of the default film. Cannot fail.
std::shared_ptr<const FilmFieldModel> MakeCrossTalkFarField();

class FilmCrossTalk {
 public:
  // `far_field` must be valid at the other chips and the reference (MakeCrossTalkFarField). The
  // sensors' mountings and the reference position are taken from `tactile` and `reference`, which
  // must outlive this.
  FilmCrossTalk(std::shared_ptr<const FilmFieldModel> far_field,
                const std::array<TactileSensorParams, kTactileSensorCount>& tactile,
                const TactileSensorParams& reference);

  // The chips' positions (body frame) and the films' poses (each in its own chip's frame) now.
  // O(1) when nothing moved; otherwise 36 film evaluations. Does not allocate.
  void Update(const std::array<Eigen::Vector3d, kTactileSensorCount>& chip_position_body_m,
              const std::array<FilmPose, kTactileSensorCount>& film_pose);

  // The other five films' field at tactile chip `sensor` (0..5), in its sensor frame.
  const Eigen::Vector3d& AtTactileSensor(int sensor) const { return at_tactile_t_[sensor]; }
  // The six films' field at the reference chip, in its sensor frame.
  const Eigen::Vector3d& AtReferenceSensor() const { return at_reference_t_; }
  // How many times the fields were recomputed.
  std::uint64_t recomputations() const { return recomputations_; }

 private:
  // Film i's field at `point_body_m`, in body axes.
  Eigen::Vector3d FilmFieldAtBody(int film, const Eigen::Vector3d& point_body_m) const;

  std::shared_ptr<const FilmFieldModel> far_field_;
  std::array<Eigen::Matrix3d, kTactileSensorCount> body_from_sensor_;
  Eigen::Matrix3d reference_from_body_;
  Eigen::Vector3d reference_position_body_m_;
  bool computed_ = false;
  std::array<Eigen::Vector3d, kTactileSensorCount> chip_position_body_m_;
  std::array<FilmPose, kTactileSensorCount> film_pose_;
  std::array<Eigen::Vector3d, kTactileSensorCount> at_tactile_t_;
  Eigen::Vector3d at_reference_t_ = Eigen::Vector3d::Zero();
  std::uint64_t recomputations_ = 0;
};

}  // namespace hilrig::host
