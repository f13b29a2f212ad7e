#include "host/sensors/tactile/cuboid_field.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace hilrig::host {
namespace {

// Coordinates are indexed [axis][side] with side 0 = "hi" (q + h, always > 0 after the reflection
// into the positive octant) and side 1 = "lo" (q - h, either sign).
constexpr int kHi = 0;
constexpr int kLo = 1;

// ∫_{lo}^{hi} dv / sqrt(v² + rho2): the in-plane field of a charged face integrated along one edge.
// r_hi, r_lo are the distances to the two ends; hi > 0 always.
double EdgeLog(double hi, double lo, double r_hi, double r_lo, double rho2, double length,
               bool* singular) {
  if (lo >= 0) {
    // The segment lies wholly on one side of the foot point: log of a ratio close to one far away.
    // (hi + r_hi) - (lo + r_lo) = length (1 + (hi + lo) / (r_hi + r_lo)) exactly, so log1p of
    // that over (lo + r_lo) keeps full relative precision at any distance.
    const double denom = lo + r_lo;
    if (denom == 0.0) {
      *singular = true;
      return 0.0;
    }
    return std::log1p(length * (1.0 + (hi + lo) / (r_hi + r_lo)) / denom);
  }
  // The segment straddles the foot point; lo + r_lo would cancel, but equals rho2 / (r_lo - lo).
  if (rho2 == 0.0) {
    *singular = true;  // On the edge line itself: the log diverges.
    return 0.0;
  }
  return std::log(hi + r_hi) + std::log(r_lo - lo) - std::log(rho2);
}

// atan(u_hi v / (w r_hi)) - atan(u_lo v / (w r_lo)) for w > 0, u_hi > 0, width = u_hi - u_lo.
double AtanPair(double u_hi, double u_lo, double v, double w, double r_hi, double r_lo,
                double width) {
  if (u_lo >= 0.0) {
    // Same-sign arguments: combine into one atan so the near-equal terms far away do not cancel.
    // d = u_hi r_lo - u_lo r_hi, formed from the exact difference u_hi² r_lo² - u_lo² r_hi².
    const double s2 = v * v + w * w;
    const double d = s2 * width * (u_hi + u_lo) / (u_hi * r_lo + u_lo * r_hi);
    return std::atan2(v * w * d, w * w * r_hi * r_lo + v * v * u_hi * u_lo);
  }
  return std::atan2(u_hi * v, w * r_hi) - std::atan2(u_lo * v, w * r_lo);
}

// Solid angle of the rectangle [u_lo, u_hi] x [v_lo, v_hi] seen from height w > 0 above its plane;
// r[iu][iv] are the corner distances.
double RectSolidAngle(double u_hi, double u_lo, double v_hi, double v_lo, double w,
                      const double r[2][2], double len_u, double len_v) {
  if (u_lo < 0.0 && v_lo >= 0.0) {
    // Outside along v only: pair the terms along v, where they are nearly equal.
    const double rt[2][2] = {{r[kHi][kHi], r[kLo][kHi]}, {r[kHi][kLo], r[kLo][kLo]}};
    return RectSolidAngle(v_hi, v_lo, u_hi, u_lo, w, rt, len_v, len_u);
  }
  return AtanPair(u_hi, u_lo, v_hi, w, r[kHi][kHi], r[kLo][kHi], len_u) -
         AtanPair(u_hi, u_lo, v_lo, w, r[kHi][kLo], r[kLo][kLo], len_u);
}

struct Corners {
  double c[3][2];     // corner coordinates relative to the point, per axis and side
  double len[3];      // side lengths
  double r[2][2][2];  // distances to the corners, [x side][y side][z side]

  double R(int axis_a, int side_a, int axis_b, int side_b, int axis_c, int side_c) const {
    int s[3];
    s[axis_a] = side_a;
    s[axis_b] = side_b;
    s[axis_c] = side_c;
    return r[s[0]][s[1]][s[2]];
  }

  // Signed solid angle of the face normal to axis n on side k (offset c[n][k]); zero on its plane,
  // the principal value between +-2π.
  double FaceSolidAngle(int n, int k) const {
    const double w = c[n][k];
    if (w == 0.0) return 0.0;
    const int p = (n + 1) % 3;
    const int q = (n + 2) % 3;
    double rr[2][2];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) rr[i][j] = R(n, k, p, i, q, j);
    }
    const double omega =
        RectSolidAngle(c[p][kHi], c[p][kLo], c[q][kHi], c[q][kLo], std::abs(w), rr, len[p], len[q]);
    return w > 0.0 ? omega : -omega;
  }

  // Integral of 1/R along the edge parallel to axis e at sides (i, j) of the two other axes a, b.
  double EdgeIntegral(int e, int a, int i, int b, int j, bool* singular) const {
    const double rho2 = c[a][i] * c[a][i] + c[b][j] * c[b][j];
    return EdgeLog(c[e][kHi], c[e][kLo], R(e, kHi, a, i, b, j), R(e, kLo, a, i, b, j), rho2, len[e],
                   singular);
  }

  // Mixed second difference over the two sides of axes a and b of the edge integrals along e: the
  // off-diagonal element N_ab of the field tensor (B = N J / 4π).
  double OffDiagonal(int e, int a, int b, bool* singular) const {
    return EdgeIntegral(e, a, kLo, b, kLo, singular) - EdgeIntegral(e, a, kHi, b, kLo, singular) -
           EdgeIntegral(e, a, kLo, b, kHi, singular) + EdgeIntegral(e, a, kHi, b, kHi, singular);
  }
};

}  // namespace

CuboidFieldResult CuboidField(const Eigen::Vector3d& half_size_m,
                              const Eigen::Vector3d& polarization_t,
                              const Eigen::Vector3d& point_m) {
  CuboidFieldResult result;
  // The cuboid is symmetric under each axis mirror, and B mirrors with J, so evaluate at the
  // reflected point with the reflected polarization and mirror the result back.
  Eigen::Vector3d sign;
  Eigen::Vector3d q;
  int on_surface = 0;
  int inside = 0;
  for (int i = 0; i < 3; ++i) {
    sign[i] = point_m[i] < 0.0 ? -1.0 : 1.0;
    q[i] = std::abs(point_m[i]);
    if (q[i] == half_size_m[i]) {
      ++on_surface;
    } else if (q[i] < half_size_m[i]) {
      ++inside;
    }
  }
  if (on_surface >= 2 && on_surface + inside == 3) {
    result.on_edge = true;
    return result;
  }
  const Eigen::Vector3d j = sign.cwiseProduct(polarization_t);

  Corners k;
  for (int i = 0; i < 3; ++i) {
    k.c[i][kHi] = q[i] + half_size_m[i];
    k.c[i][kLo] = q[i] - half_size_m[i];
    k.len[i] = 2.0 * half_size_m[i];
  }
  for (int ix = 0; ix < 2; ++ix) {
    for (int iy = 0; iy < 2; ++iy) {
      for (int iz = 0; iz < 2; ++iz) {
        k.r[ix][iy][iz] =
            std::sqrt(k.c[0][ix] * k.c[0][ix] + k.c[1][iy] * k.c[1][iy] + k.c[2][iz] * k.c[2][iz]);
      }
    }
  }

  // Only the tensor elements that meet a non-zero polarization component are evaluated: the film's
  // tiles are mostly in-plane, and the atan terms of the unused diagonal are the costliest part.
  bool singular = false;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int n = 0; n < 3; ++n) {
    if (j[n] == 0.0) continue;
    // The face at +h (offset c[n][kLo]) carries charge +J_n, the one at -h carries -J_n.
    b[n] += j[n] * (k.FaceSolidAngle(n, kLo) - k.FaceSolidAngle(n, kHi));
  }
  if (j[0] != 0.0 || j[1] != 0.0) {
    const double nxy = k.OffDiagonal(2, 0, 1, &singular);
    b[0] += nxy * j[1];
    b[1] += nxy * j[0];
  }
  if (j[0] != 0.0 || j[2] != 0.0) {
    const double nxz = k.OffDiagonal(1, 0, 2, &singular);
    b[0] += nxz * j[2];
    b[2] += nxz * j[0];
  }
  if (j[1] != 0.0 || j[2] != 0.0) {
    const double nyz = k.OffDiagonal(0, 1, 2, &singular);
    b[1] += nyz * j[2];
    b[2] += nyz * j[1];
  }
  if (singular) {
    // Only reachable when a distance underflows to zero right next to an edge.
    result.on_edge = true;
    return result;
  }
  b /= 4.0 * std::numbers::pi;
  if (on_surface + inside == 3) {
    // Inside: B = µ0 H + J; on a face, half of J (the mean of the limits from both sides).
    b += (on_surface == 0 ? 1.0 : 0.5) * j;
  }
  result.field_t = sign.cwiseProduct(b);
  return result;
}

}  // namespace hilrig::host
