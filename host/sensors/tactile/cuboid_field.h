// Closed-form flux density of a uniformly polarized, axis-aligned cuboid: the building block of the
// tiled film model (film_magnet.h). The formulas are the surface-charge ones of Yang (1990) and
// Camacho & Sosa (2013): each face carries a charge J·n, its normal field is the solid angle the
// face subtends and its in-plane field is a sum of logarithms along the face's edges. They are
// re-derived here in a form that stays accurate everywhere, after Cichon (2019): the observation
// point is reflected into the octant x, y, z >= 0, where every log and atan term is evaluated on
// the side where it is well conditioned, and the pairs that cancel far from the cuboid are formed
// from exact differences (side lengths) instead of by subtraction, so the relative round-off grows
// only like 1e-16 (distance/size)^2: about 1e-9 at 1000x the cuboid size.
//
// Conventions at the surface: on a face (not an edge) the value returned is the mean of the limits
// from both sides, i.e. the component of B tangential to the face that jumps by J_t is returned
// half-way; the normal component is continuous anyway. On an edge or a corner the field of a
// charged face diverges logarithmically; there the result is flagged (on_edge) and is zero.
#pragma once

#include <Eigen/Core>

namespace hilrig::host {

struct CuboidFieldResult {
  Eigen::Vector3d field_t = Eigen::Vector3d::Zero();
  // True when the point lies exactly on an edge or corner of the cuboid; field_t is zero then.
  bool on_edge = false;
};

// B in tesla at point_m, all in the cuboid's frame (centre at the origin, faces normal to the axes,
// extents ±half_size_m). polarization_t is J = µ0 M in tesla, any direction. Inside the cuboid the
// result is B = µ0 H + J.
CuboidFieldResult CuboidField(const Eigen::Vector3d& half_size_m,
                              const Eigen::Vector3d& polarization_t,
                              const Eigen::Vector3d& point_m);

}  // namespace hilrig::host
