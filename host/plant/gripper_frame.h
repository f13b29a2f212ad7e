// Geometry of the deformable central frame that grasps: one servo shrinks the frame, which moves
// the six tactile pads on its inner wall radially toward the frame centre. The frame angle is the
// servo angle; every pad's contact surface (the film) sits at PadSurfaceRadius(angle) from the
// frame centre and the Hall chip a fixed standoff behind it (outward). The pads TRANSLATE
// radially: their orientation does not change with the angle, so the contact normal
// n_i = -outward_i and the sensor mounting R_BS of sensor_layout.h stay fixed while the frame
// closes (only the chip position moves). Pads sit every 60 deg counter-clockwise (seen from above)
// from first_azimuth_rad, matching the sensor layout's ring, in the plane height_m above the body
// origin.
#ifndef HILRIG_HOST_PLANT_GRIPPER_FRAME_H_
#define HILRIG_HOST_PLANT_GRIPPER_FRAME_H_

#include <Eigen/Core>
#include <numbers>

#include "rig/result.h"

namespace hilrig::host {

struct GripperFrameParams {
  double open_radius_m = 0.055;      // pad surface (film) distance from the frame centre at angle 0
  double closing_m_per_rad = 0.025;  // every pad moves this far inward per radian of servo angle
  double film_standoff_m = 0.010;    // Hall chip behind the pad surface (outward)
  double height_m = 0.0;             // ring plane above the body origin
  double first_azimuth_rad =
      std::numbers::pi / 6;  // pads every 60 deg from here, counter-clockwise
};

inline constexpr int kGripperPadCount = 6;

// Finite, open radius > 0, closing > 0, standoff >= 0; the message names the field.
rig::Result<void> ValidateGripperFrame(const GripperFrameParams& params);

// open - closing * angle, never below 0. A NaN angle reads as the open frame (radius at angle 0).
double PadSurfaceRadius(const GripperFrameParams& params, double angle_rad);
// Unit vector from the frame centre toward pad `pad` (0..5), body frame, horizontal. Aborts on a
// pad index outside 0..5 (a programming error).
Eigen::Vector3d PadOutwardBody(const GripperFrameParams& params, int pad);
// Centre of the pad's contact surface, body frame.
Eigen::Vector3d PadSurfaceBody(const GripperFrameParams& params, int pad, double angle_rad);
// The Hall chip: the surface point plus the standoff, outward.
Eigen::Vector3d ChipPositionBody(const GripperFrameParams& params, int pad, double angle_rad);
// Inverse of PadSurfaceRadius: (open - radius) / closing. Returns 0 for a non-finite radius or a
// frame that does not close (closing <= 0), so callers never get a NaN angle.
double AngleForPadRadius(const GripperFrameParams& params, double radius_m);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_GRIPPER_FRAME_H_
