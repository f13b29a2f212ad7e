#include "dut_fw/mixer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class MixerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(MixerTest, Scalars);

template <typename S>
MixerGeometry<S> Geometry() {
  return MixerGeometry<S>{S(0.1), S(0.016), S(4)};
}

// (collective, τx, τy, τz) produced by the given rotor thrusts.
template <typename S>
Eigen::Matrix<S, 4, 1> Wrench(const std::array<S, 4>& thrust_n) {
  return AllocationMatrix(Geometry<S>()) *
         Eigen::Matrix<S, 4, 1>(thrust_n[0], thrust_n[1], thrust_n[2], thrust_n[3]);
}

TYPED_TEST(MixerTest, AllocationMatrixMatchesTheSharedLayout) {
  using S = TypeParam;
  const double a = 0.1 / std::sqrt(2.0);

  const Eigen::Matrix<S, 4, 4> m = AllocationMatrix(Geometry<S>());

  // Rotor 0 at (+a, -a) with yaw sign -1: r × (0,0,1) = (y, -x, 0) = (-a, -a, 0).
  EXPECT_NEAR(m(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(m(1, 0), -a, 1e-7);
  EXPECT_NEAR(m(2, 0), -a, 1e-7);
  EXPECT_NEAR(m(3, 0), -0.016, 1e-7);
  // Rotor 2 at (+a, +a) with yaw sign +1.
  EXPECT_NEAR(m(1, 2), a, 1e-7);
  EXPECT_NEAR(m(2, 2), -a, 1e-7);
  EXPECT_NEAR(m(3, 2), 0.016, 1e-7);
}

TYPED_TEST(MixerTest, ConstantsAreTheInverseRowNorms) {
  using S = TypeParam;

  const MixerConstants<S> c = MixerConstantsOf(Geometry<S>());

  // a = 0.1/√2, so 1/(4a) = √2/0.4 = 3.5355339...; 4κ = 0.064.
  EXPECT_NEAR(c.inv_4a, 3.5355339059327378, 1e-6);
  EXPECT_NEAR(c.four_kappa_m, 0.064, 1e-8);
  EXPECT_EQ(c.max_thrust_per_rotor_n, S(4));
}

TYPED_TEST(MixerTest, MixIntoOverwritesEveryRotor) {
  using S = TypeParam;
  std::array<S, 4> thrust_n = {S(9), S(9), S(9), S(9)};

  MixInto<S>(MixerConstantsOf(Geometry<S>()), S(8), Vec3<S>::Zero(), thrust_n);

  for (S t : thrust_n) EXPECT_EQ(t, S(2));
  MixInto<S>(MixerConstantsOf(Geometry<S>()), std::numeric_limits<S>::quiet_NaN(), Vec3<S>::Zero(),
             thrust_n);
  for (S t : thrust_n) EXPECT_EQ(t, S(0));
}

TYPED_TEST(MixerTest, PureCollectiveSplitsEqually) {
  using S = TypeParam;

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(8), Vec3<S>::Zero());

  for (S v : t) EXPECT_NEAR(v, 2.0, 1e-6);
}

TYPED_TEST(MixerTest, RollTorqueRoundTripsThroughTheAllocationMatrix) {
  using S = TypeParam;

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(6), Vec3<S>(S(0.05), S(0), S(0)));

  const Eigen::Matrix<S, 4, 1> w = Wrench<S>(t);
  EXPECT_NEAR(w(0), 6.0, 1e-5);
  EXPECT_NEAR(w(1), 0.05, 1e-6);
  EXPECT_NEAR(w(2), 0.0, 1e-6);
  EXPECT_NEAR(w(3), 0.0, 1e-6);
  // Positive roll (about +x) lifts the left rotors 1 and 2.
  EXPECT_GT(t[1], t[0]);
  EXPECT_GT(t[2], t[3]);
}

TYPED_TEST(MixerTest, GeneralWrenchRoundTrips) {
  using S = TypeParam;
  const Vec3<S> torque(S(0.03), S(-0.02), S(0.01));

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(5.5), torque);

  const Eigen::Matrix<S, 4, 1> w = Wrench<S>(t);
  EXPECT_NEAR(w(0), 5.5, 1e-5);
  EXPECT_NEAR(w(1), 0.03, 1e-6);
  EXPECT_NEAR(w(2), -0.02, 1e-6);
  EXPECT_NEAR(w(3), 0.01, 1e-6);
}

TYPED_TEST(MixerTest, SaturationKeepsRollPitchAndGivesUpYawAndCollective) {
  using S = TypeParam;
  // Near full collective with a large torque demand on every axis.
  const Vec3<S> torque(S(0.2), S(-0.1), S(0.05));

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(15.5), torque);

  for (S v : t) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 4.0);
  }
  const Eigen::Matrix<S, 4, 1> w = Wrench<S>(t);
  EXPECT_NEAR(w(1), 0.2, 1e-5);
  EXPECT_NEAR(w(2), -0.1, 1e-5);
  EXPECT_LT(w(0), 15.5);   // collective gave way
  EXPECT_LT(w(3), 0.05);   // yaw gave way
  EXPECT_GE(w(3), -1e-6);  // but never reversed
}

TYPED_TEST(MixerTest, ImpossibleRollPitchIsScaledKeepingItsDirection) {
  using S = TypeParam;
  const Vec3<S> torque(S(2.0), S(1.0), S(0.0));  // ~4x what the rotors can do

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(5.5), torque);

  for (S v : t) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 4.0);
  }
  const Eigen::Matrix<S, 4, 1> w = Wrench<S>(t);
  EXPECT_NEAR(w(1) / w(2), 2.0, 1e-5);
  // The strongest achievable torque along that direction uses the full range on one diagonal.
  EXPECT_NEAR(*std::max_element(t.begin(), t.end()) - *std::min_element(t.begin(), t.end()), 4.0,
              1e-5);
}

TYPED_TEST(MixerTest, LowCollectiveIsRaisedToKeepRollTorque) {
  using S = TypeParam;

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(0.2), Vec3<S>(S(0.1), S(0), S(0)));

  const Eigen::Matrix<S, 4, 1> w = Wrench<S>(t);
  EXPECT_NEAR(w(1), 0.1, 1e-6);
  EXPECT_NEAR(*std::min_element(t.begin(), t.end()), 0.0, 1e-6);
  EXPECT_GT(w(0), 0.2);
}

TYPED_TEST(MixerTest, PositiveYawTorqueUsesThePositiveSignRotors) {
  using S = TypeParam;

  const std::array<S, 4> t = Mix<S>(Geometry<S>(), S(6), Vec3<S>(S(0), S(0), S(0.016)));

  // Each of rotors 2, 3 gets +0.25 N, rotors 0, 1 -0.25 N.
  EXPECT_NEAR(t[0], 1.25, 1e-6);
  EXPECT_NEAR(t[1], 1.25, 1e-6);
  EXPECT_NEAR(t[2], 1.75, 1e-6);
  EXPECT_NEAR(t[3], 1.75, 1e-6);
}

TYPED_TEST(MixerTest, NonFiniteInputStopsAllRotors) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();

  const std::array<S, 4> a = Mix<S>(Geometry<S>(), nan, Vec3<S>::Zero());
  const std::array<S, 4> b = Mix<S>(Geometry<S>(), S(5), Vec3<S>(S(0), nan, S(0)));

  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(a[i], S(0));
    EXPECT_EQ(b[i], S(0));
  }
}

}  // namespace
}  // namespace hilrig::dut_fw
