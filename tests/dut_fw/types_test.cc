#include "dut_fw/types.h"

#include <gtest/gtest.h>

#include <limits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class TypesTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(TypesTest, Scalars);

TYPED_TEST(TypesTest, HatIsTheCrossProduct) {
  using S = TypeParam;
  const Vec3<S> a(S(0.3), S(-1.2), S(2.0));
  const Vec3<S> b(S(-0.7), S(0.4), S(1.1));

  const Vec3<S> via_hat = Hat<S>(a) * b;

  EXPECT_NEAR(via_hat.x(), a.cross(b).x(), 1e-6);
  EXPECT_NEAR(via_hat.y(), a.cross(b).y(), 1e-6);
  EXPECT_NEAR(via_hat.z(), a.cross(b).z(), 1e-6);
}

TYPED_TEST(TypesTest, VeeInvertsHat) {
  using S = TypeParam;
  const Vec3<S> a(S(0.3), S(-1.2), S(2.0));

  const Vec3<S> back = Vee<S>(Hat<S>(a));

  EXPECT_EQ(back, a);
}

TYPED_TEST(TypesTest, QuatExpMatchesAngleAxisForLargeAngles) {
  using S = TypeParam;
  const Vec3<S> axis = Vec3<S>(S(1), S(2), S(-2)).normalized();
  const S angle = S(2.5);

  const Quat<S> q = QuatExp<S>(axis * angle);

  const Quat<S> expected(Eigen::AngleAxis<S>(angle, axis));
  EXPECT_NEAR(q.angularDistance(expected), 0.0, 1e-5);
  EXPECT_NEAR(q.norm(), 1.0, 1e-6);
}

TYPED_TEST(TypesTest, QuatExpIsAccurateForTinyAngles) {
  using S = TypeParam;
  const Vec3<S> v(S(1e-4), S(-2e-4), S(0.5e-4));

  const Quat<S> q = QuatExp<S>(v);

  EXPECT_NEAR(q.w(), 1.0, 1e-7);
  EXPECT_NEAR(q.x(), 0.5e-4, 1e-9);
  EXPECT_NEAR(q.y(), -1e-4, 1e-9);
  EXPECT_NEAR(q.z(), 0.25e-4, 1e-9);
  EXPECT_NEAR(q.norm(), 1.0, 1e-7);
}

TYPED_TEST(TypesTest, QuatErrorVectorTakesTheShortArc) {
  using S = TypeParam;
  const Quat<S> q = QuatExp<S>(Vec3<S>(S(0), S(0), S(0.4)));
  const Quat<S> negated(-q.w(), -q.x(), -q.y(), -q.z());  // the same rotation

  const Vec3<S> e = QuatErrorVector<S>(q);
  const Vec3<S> e_negated = QuatErrorVector<S>(negated);

  EXPECT_NEAR(e.z(), 2.0 * std::sin(0.2), 1e-6);
  EXPECT_NEAR(e_negated.z(), e.z(), 1e-7);
}

TYPED_TEST(TypesTest, AllFiniteSpotsNanAndInf) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const S inf = std::numeric_limits<S>::infinity();

  EXPECT_TRUE(AllFinite(Vec3<S>(S(1), S(2), S(3))));
  EXPECT_FALSE(AllFinite(Vec3<S>(S(1), nan, S(3))));
  EXPECT_FALSE(AllFinite(Vec3<S>(S(1), S(2), -inf)));
  EXPECT_FALSE(AllFinite(Quat<S>(S(1), S(0), S(0), nan)));
}

}  // namespace
}  // namespace hilrig::dut_fw
