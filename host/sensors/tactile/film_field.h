// The seam between the magnetics of a tactile sensor and the rest of its forward model: the field
// that the magnetized film produces at the Hall chip, for a given pose of the film relative to the
// chip. Fidelity levels (N x N cuboid tiles, a tabulated field map, a dipole fake for tests)
// implement it; the silicone and MLX90393 models only see this interface.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hilrig::host {

// Pose of the film's own frame (origin at the film centre, z along the film normal) in the chip
// frame. At rest the film sits straight below the chip: centre (0, 0, -10 mm), no rotation.
struct FilmPose {
  Eigen::Vector3d centre_m = Eigen::Vector3d(0, 0, -0.010);
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

class FilmFieldModel {
 public:
  virtual ~FilmFieldModel() = default;
  // Flux density in tesla at the chip (the origin of the chip frame), in chip axes.
  virtual Eigen::Vector3d FieldAtChip(const FilmPose& pose) const = 0;
};

}  // namespace hilrig::host
