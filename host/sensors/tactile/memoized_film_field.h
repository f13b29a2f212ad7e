// A film field model that remembers its last answer. A pad with nothing touching it keeps its
// film at exactly the rest pose, sample after sample, so a scene without contact pays for one
// field evaluation per node instead of one per sample, with bit-identical results. The memo is an
// exact cache, not state: the answer for a pose never depends on what was asked before.
#pragma once

#include <memory>

#include "host/sensors/tactile/film_field.h"

namespace hilrig::host {

class MemoizedFilmField final : public FilmFieldModel {
 public:
  explicit MemoizedFilmField(std::shared_ptr<const FilmFieldModel> source)
      : source_(std::move(source)) {}

  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override {
    if (!has_last_ || pose.centre_m != last_pose_.centre_m ||
        pose.orientation.coeffs() != last_pose_.orientation.coeffs()) {
      last_field_t_ = source_->FieldAtChip(pose);
      last_pose_ = pose;
      has_last_ = true;
    }
    return last_field_t_;
  }

 private:
  std::shared_ptr<const FilmFieldModel> source_;
  mutable bool has_last_ = false;
  mutable FilmPose last_pose_;
  mutable Eigen::Vector3d last_field_t_ = Eigen::Vector3d::Zero();
};

}  // namespace hilrig::host
