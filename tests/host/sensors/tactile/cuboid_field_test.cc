#include "host/sensors/tactile/cuboid_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "host/sensors/tactile/dipole_film_field.h"

namespace hilrig::host {
namespace {

constexpr double kMu0 = 4e-7 * std::numbers::pi;

// A deliberately non-cubic tile (a cube has no quadrupole, so its dipole error falls faster).
const Eigen::Vector3d kHalf(0.3e-3, 0.2e-3, 0.05e-3);
const Eigen::Vector3d kJ(0.1, -0.2, 0.15);

Eigen::Vector3d Field(const Eigen::Vector3d& half, const Eigen::Vector3d& j,
                      const Eigen::Vector3d& p) {
  const CuboidFieldResult r = CuboidField(half, j, p);
  EXPECT_FALSE(r.on_edge) << p.transpose();
  return r.field_t;
}

std::vector<Eigen::Vector3d> Directions() {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Vector3d> dirs = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                       Eigen::Vector3d::UnitZ()};
  for (int i = 0; i < 5; ++i) dirs.push_back(Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized());
  return dirs;
}

TEST(CuboidFieldTest, ApproachesDipoleWithErrorShrinkingAsSizeOverDistanceSquared) {
  // Setup
  const double size = 2.0 * kHalf.maxCoeff();
  const Eigen::Vector3d moment = kJ / kMu0 * 8.0 * kHalf.prod();
  for (const Eigen::Vector3d& dir : Directions()) {
    double rel[3];
    const double ratios[3] = {100.0, 300.0, 1000.0};
    for (int i = 0; i < 3; ++i) {
      // Run
      const Eigen::Vector3d p = dir * ratios[i] * size;
      const Eigen::Vector3d dipole = PointDipoleField(moment, p);
      rel[i] = (Field(kHalf, kJ, p) - dipole).norm() / dipole.norm();
    }
    // Check: the quadrupole correction, relative (size/distance)^2, and nothing else; the 5%
    // slack at 1000x is round-off, about 1e-9 of the field there.
    EXPECT_LT(rel[0], 1e-3 * std::pow(100.0 / ratios[0], 2)) << dir.transpose();
    EXPECT_NEAR(rel[0] / rel[1], 9.0, 0.2) << dir.transpose();
    EXPECT_NEAR(rel[1] / rel[2], 1000.0 * 1000.0 / (300.0 * 300.0), 0.5) << dir.transpose();
  }
}

TEST(CuboidFieldTest, MirroredPointGivesMirroredField) {
  // Setup
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d m = Eigen::Vector3d::Ones();
      m[axis] = -1.0;
      // Run
      const Eigen::Vector3d direct = Field(kHalf, kJ, p);
      const Eigen::Vector3d mirrored = Field(kHalf, m.cwiseProduct(kJ), m.cwiseProduct(p));
      // Check
      EXPECT_LT((mirrored - m.cwiseProduct(direct)).norm(), 1e-12 * direct.norm() + 1e-15);
    }
  }
}

TEST(CuboidFieldTest, PermutingAxesPermutesField) {
  // Setup: a cyclic permutation of the axes of point, size and polarization.
  auto perm = [](const Eigen::Vector3d& v) { return Eigen::Vector3d(v.z(), v.x(), v.y()); };
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.5e-3, 1.5e-3);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    // Run
    const Eigen::Vector3d direct = Field(kHalf, kJ, p);
    const Eigen::Vector3d permuted = Field(perm(kHalf), perm(kJ), perm(p));
    // Check
    EXPECT_LT((permuted - perm(direct)).norm(), 1e-11 * direct.norm());
  }
}

TEST(CuboidFieldTest, NormalComponentContinuousAndTangentialJumpsByJAcrossFaces) {
  // Setup: points just inside and just outside each face, and on it.
  const double eps = 1e-14;  // the field's own gradient (~J/size) must not show
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d on(0.4 * kHalf.x(), -0.3 * kHalf.y(), 0.2 * kHalf.z());
    on[axis] = kHalf[axis];
    Eigen::Vector3d in = on;
    in[axis] -= eps;
    Eigen::Vector3d out = on;
    out[axis] += eps;
    // Run
    const Eigen::Vector3d b_in = Field(kHalf, kJ, in);
    const Eigen::Vector3d b_out = Field(kHalf, kJ, out);
    const Eigen::Vector3d b_on = Field(kHalf, kJ, on);
    // Check: B·n continuous; B_t jumps by J_t (H_t continuous); on the face, the mean.
    for (int c = 0; c < 3; ++c) {
      const double jump = c == axis ? 0.0 : kJ[c];
      EXPECT_NEAR(b_in[c] - b_out[c], jump, 1e-9) << "axis " << axis << " comp " << c;
      EXPECT_NEAR(b_on[c], 0.5 * (b_in[c] + b_out[c]), 1e-9) << "axis " << axis << " comp " << c;
    }
  }
}

TEST(CuboidFieldTest, FiniteOnFacePlanesEdgeLinesAndNearEdgesFlaggedOnEdges) {
  // Setup: every combination of coordinates from {inside, on the face plane, outside} per axis.
  const double vals[] = {0.0, 0.5, 1.0, 1.0 + 1e-13, 2.0, -1.0, -2.0};
  int flagged = 0;
  for (double fx : vals) {
    for (double fy : vals) {
      for (double fz : vals) {
        const Eigen::Vector3d p(fx * kHalf.x(), fy * kHalf.y(), fz * kHalf.z());
        // Run
        const CuboidFieldResult r = CuboidField(kHalf, kJ, p);
        // Check
        ASSERT_TRUE(r.field_t.allFinite()) << p.transpose();
        int on = 0;
        int within = 0;
        for (double f : {fx, fy, fz}) {
          on += std::abs(f) == 1.0;
          within += std::abs(f) <= 1.0;
        }
        const bool edge = on >= 2 && within == 3;
        EXPECT_EQ(r.on_edge, edge) << p.transpose();
        flagged += r.on_edge;
        if (!edge) {
          EXPECT_LT(r.field_t.norm(), 10.0 * kJ.norm()) << p.transpose();
        }
      }
    }
  }
  // Edges: 3 axes x 2 inner values x 4 sign pairs; corners: 8.
  EXPECT_EQ(flagged, 3 * 2 * 4 + 8);
}

TEST(CuboidFieldTest, TwoHalvesSumToTheWhole) {
  // Setup: split along x into [-a, 0] and [0, a].
  const Eigen::Vector3d half_half(kHalf.x() / 2.0, kHalf.y(), kHalf.z());
  const Eigen::Vector3d shift(kHalf.x() / 2.0, 0.0, 0.0);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (int trial = 0; trial < 100; ++trial) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (trial % 10 == 0) p.x() = 0.0;                       // on the shared face
    if (trial % 10 == 1) p = p.cwiseProduct(kHalf / 1e-3);  // inside
    // Run
    const Eigen::Vector3d whole = Field(kHalf, kJ, p);
    const Eigen::Vector3d sum = Field(half_half, kJ, p + shift) + Field(half_half, kJ, p - shift);
    // Check
    EXPECT_LT((sum - whole).norm(), 1e-10 * whole.norm() + 1e-14) << p.transpose();
  }
}

// On the axis of a z-polarized cuboid each z-face subtends 4 atan(ab / (h sqrt(a²+b²+h²))), so
// Bz(z) = (J/π)[atan(ab / ((z-c) r1)) - atan(ab / ((z+c) r2))] (+ J inside, where z-c < 0).
double AxialBz(double a, double b, double c, double j, double z) {
  auto term = [&](double h) { return std::atan(a * b / (h * std::sqrt(a * a + b * b + h * h))); };
  return j / std::numbers::pi * (term(z - c) - term(z + c)) + (std::abs(z) < c ? j : 0.0);
}

TEST(CuboidFieldTest, OnAxisFieldMatchesClosedForm) {
  // Setup
  const double a = 2e-3, b = 1e-3, c = 0.5e-3, j = 0.3;
  for (double z : {-5e-3, -0.7e-3, -0.2e-3, 0.0, 0.3e-3, 0.51e-3, 1e-3, 10e-3}) {
    // Run
    const Eigen::Vector3d field =
        Field(Eigen::Vector3d(a, b, c), Eigen::Vector3d(0, 0, j), Eigen::Vector3d(0, 0, z));
    // Check
    EXPECT_NEAR(field.z(), AxialBz(a, b, c, j, z), 1e-14) << z;
    EXPECT_NEAR(field.x(), 0.0, 1e-15);
    EXPECT_NEAR(field.y(), 0.0, 1e-15);
  }
}

TEST(CuboidFieldTest, CubeCentreFieldIsTwoThirdsOfJ) {
  // Setup: the demagnetizing factor of a cube is 1/3 along any axis.
  const Eigen::Vector3d j(0.1, -0.4, 0.25);
  // Run
  const Eigen::Vector3d field = Field(Eigen::Vector3d::Constant(1e-3), j, Eigen::Vector3d::Zero());
  // Check
  EXPECT_LT((field - 2.0 / 3.0 * j).norm(), 1e-15);
}

}  // namespace
}  // namespace hilrig::host
