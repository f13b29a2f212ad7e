#include "dut_fw/tactile_decoding.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class TactileDecodingTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(TactileDecodingTest, Scalars);

template <typename S>
Vec3<S> FieldMilliTesla(double bx, double by, double bz) {
  return Vec3<S>(S(bx * 1e-3), S(by * 1e-3), S(bz * 1e-3));
}

// A film whose Bz' is Bz itself, so a test can put Bz' exactly where it wants it.
template <typename S>
FilmConstants<S> IdentityPrimeFilm() {
  FilmConstants<S> film = FilmConstants<S>::Published();
  film.k1 = S(1);
  film.c1 = S(0);
  return film;
}

template <typename S>
FilmConstants<S> IdentityDoublePrimeFilm() {
  FilmConstants<S> film = FilmConstants<S>::Published();
  film.k2 = S(1);
  film.c2 = S(0);
  return film;
}

// The printed formulas, transcribed literally (with Bz''² in S_z) and evaluated in long double.
// Valid only where the printed atan denominators are positive, which the working volume is.
Vec3<double> LiteralS(const FilmConstants<double>& film, const Vec3<double>& b) {
  using L = long double;
  const L bx = b.x(), by = b.y(), bz = b.z();
  const L bz1 = L(film.k1) * bz + L(film.c1);
  const L bz2 = L(film.k2) * bz + L(film.c2);
  const L sx = std::atan(bx / (bz1 - (bz1 * bz1 - (by * by - bx * bx)) / (2 * bz1)));
  const L sy = std::atan(by / (bz1 - (bz1 * bz1 + (by * by - bx * bx)) / (2 * bz1)));
  const L t = bz2 - (bz2 * bz2 + (by * by - bx * bx)) / (2 * bz2);
  const L sz = std::log(std::sqrt(t * t + by * by));
  return Vec3<double>(double(sx), double(sy), double(sz));
}

// Representative fields of the film 8-12 mm below the chip, either polarity of Bz.
constexpr double kBoxTransverseMt = 2.0;
constexpr double kBoxBzMinMt = 2.0;
constexpr double kBoxBzMaxMt = 8.0;

template <typename S>
void ExpectFlagged(const SVector<S>& out, DecodeStatus expected) {
  EXPECT_EQ(out.status, expected) << DecodeStatusName(out.status);
  EXPECT_FALSE(out.ok());
  EXPECT_EQ(out.s, Vec3<S>::Zero());
}

TYPED_TEST(TactileDecodingTest, BzPrimeExactlyZeroIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityPrimeFilm<S>();

  const SVector<S> out = ComputeS<S>(film, FieldMilliTesla<S>(1.0, 0.5, 0.0));

  ExpectFlagged(out, DecodeStatus::kBzPrimeSingular);
}

TYPED_TEST(TactileDecodingTest, BzPrimeOneUlpFromZeroIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityPrimeFilm<S>();
  const S up = std::nextafter(S(0), S(1));
  const S down = std::nextafter(S(0), S(-1));

  const SVector<S> above = ComputeS<S>(film, Vec3<S>(S(1e-3), S(5e-4), up));
  const SVector<S> below = ComputeS<S>(film, Vec3<S>(S(1e-3), S(5e-4), down));

  ExpectFlagged(above, DecodeStatus::kBzPrimeSingular);
  ExpectFlagged(below, DecodeStatus::kBzPrimeSingular);
}

TYPED_TEST(TactileDecodingTest, BzPrimeAtThePublishedFilmsZeroCrossingIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const S bz_zero = -film.c1 / film.k1;  // Bz' = 0 up to rounding

  for (const S bz : {bz_zero, std::nextafter(bz_zero, S(1)), std::nextafter(bz_zero, S(-1))}) {
    const SVector<S> out = ComputeS<S>(film, Vec3<S>(S(1e-3), S(-5e-4), bz));

    ExpectFlagged(out, DecodeStatus::kBzPrimeSingular);
  }
}

TYPED_TEST(TactileDecodingTest, BzDoublePrimeExactlyZeroIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityDoublePrimeFilm<S>();

  const SVector<S> out = ComputeS<S>(film, FieldMilliTesla<S>(1.0, 0.5, 0.0));

  ExpectFlagged(out, DecodeStatus::kBzDoublePrimeSingular);
}

TYPED_TEST(TactileDecodingTest, BzDoublePrimeOneUlpFromZeroIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityDoublePrimeFilm<S>();
  const S up = std::nextafter(S(0), S(1));
  const S down = std::nextafter(S(0), S(-1));

  const SVector<S> above = ComputeS<S>(film, Vec3<S>(S(1e-3), S(5e-4), up));
  const SVector<S> below = ComputeS<S>(film, Vec3<S>(S(1e-3), S(5e-4), down));

  ExpectFlagged(above, DecodeStatus::kBzDoublePrimeSingular);
  ExpectFlagged(below, DecodeStatus::kBzDoublePrimeSingular);
}

TYPED_TEST(TactileDecodingTest, BzDoublePrimeAtThePublishedFilmsZeroCrossingIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const S bz_zero = -film.c2 / film.k2;

  for (const S bz : {bz_zero, std::nextafter(bz_zero, S(1)), std::nextafter(bz_zero, S(-1))}) {
    const SVector<S> out = ComputeS<S>(film, Vec3<S>(S(1e-3), S(-5e-4), bz));

    ExpectFlagged(out, DecodeStatus::kBzDoublePrimeSingular);
  }
}

TYPED_TEST(TactileDecodingTest, ZeroOverZeroAtBzPrimeZeroIsIndeterminate) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityPrimeFilm<S>();

  const SVector<S> out = ComputeS<S>(film, Vec3<S>::Zero());

  ExpectFlagged(out, DecodeStatus::kIndeterminate);
}

TYPED_TEST(TactileDecodingTest, ZeroOverZeroAtBzDoublePrimeZeroIsIndeterminate) {
  using S = TypeParam;
  const FilmConstants<S> film = IdentityDoublePrimeFilm<S>();

  const SVector<S> out = ComputeS<S>(film, Vec3<S>(S(0), S(-0.0), S(0)));

  ExpectFlagged(out, DecodeStatus::kIndeterminate);
}

// Where |Bx| reaches sqrt(Bz'² + By²) the printed atan's denominator changes sign and the printed
// S_x jumps from -π/2 to +π/2; the decoder must pass through -π/2 continuously instead.
TYPED_TEST(TactileDecodingTest, AtanDenominatorCrossingZeroIsContinuous) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const S by = S(1e-3), bz = S(-3e-3);
  const long double bz1 = (long double)(film.k1) * bz + film.c1;  // < 0
  const S bx_cross = S(std::sqrt(bz1 * bz1 + (long double)(by)*by));
  const S half_pi = S(std::numbers::pi / 2);

  std::vector<S> sx;
  for (int i = -1000; i <= 1000; ++i) {
    const S bx = bx_cross * (S(1) + S(i) * S(1e-6));
    const SVector<S> out = ComputeS<S>(film, Vec3<S>(bx, by, bz));
    ASSERT_TRUE(out.ok()) << DecodeStatusName(out.status);
    sx.push_back(out.s.x());
  }
  const SVector<S> at = ComputeS<S>(film, Vec3<S>(bx_cross, by, bz));
  const SVector<S> ulp_below = ComputeS<S>(film, Vec3<S>(std::nextafter(bx_cross, S(0)), by, bz));
  const SVector<S> ulp_above = ComputeS<S>(film, Vec3<S>(std::nextafter(bx_cross, S(1)), by, bz));

  for (std::size_t i = 1; i < sx.size(); ++i) {
    EXPECT_LT(std::abs(sx[i] - sx[i - 1]), S(1e-4)) << i;
  }
  EXPECT_GT(sx.front(), -half_pi);
  EXPECT_LT(sx.back(), -half_pi);
  EXPECT_NEAR(at.s.x(), -half_pi, 1e-4);
  EXPECT_NEAR(ulp_below.s.x(), at.s.x(), 1e-5);
  EXPECT_NEAR(ulp_above.s.x(), at.s.x(), 1e-5);
}

// The trap of the obvious atan2 transcription: with Bz' < 0 it jumps by 2π as Bx (By) changes
// sign. The decoder's S_x (S_y) must pass through zero from either side, signed zeros included.
TYPED_TEST(TactileDecodingTest, TransverseSignChangeWithNegativeBzPrimeDoesNotJump) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const S bz = S(-3e-3);
  ASSERT_LT(film.k1 * bz + film.c1, S(0));
  const S tiny = std::numeric_limits<S>::denorm_min();
  const S values[] = {S(-1e-6), S(-1e-9), -tiny, S(-0.0), S(0.0), tiny, S(1e-9), S(1e-6)};

  for (int axis = 0; axis < 2; ++axis) {
    S previous = std::numeric_limits<S>::infinity();
    for (const S v : values) {
      Vec3<S> field(S(5e-4), S(5e-4), bz);
      field[axis] = v;

      const SVector<S> out = ComputeS<S>(film, field);

      ASSERT_TRUE(out.ok()) << DecodeStatusName(out.status);
      EXPECT_LT(std::abs(out.s[axis]), S(1e-3)) << axis << " " << v;
      EXPECT_LE(out.s[axis], previous) << axis << " " << v;  // Bz' < 0: decreasing in Bx (By)
      previous = out.s[axis];
    }
  }
}

TYPED_TEST(TactileDecodingTest, SignedZeroTransverseFieldsDecodeToZeroAngles) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();

  for (const S bx : {S(0.0), S(-0.0)}) {
    for (const S by : {S(0.0), S(-0.0)}) {
      for (const S bz : {S(4e-3), S(-4e-3), S(0.0), S(-0.0)}) {
        const SVector<S> out = ComputeS<S>(film, Vec3<S>(bx, by, bz));

        ASSERT_TRUE(out.ok()) << bx << " " << by << " " << bz;
        EXPECT_EQ(out.s.x(), S(0));
        EXPECT_EQ(out.s.y(), S(0));
        EXPECT_TRUE(std::isfinite(out.s.z()));
      }
    }
  }
}

TYPED_TEST(TactileDecodingTest, SignedZeroFieldWithoutOffsetsIsIndeterminate) {
  using S = TypeParam;
  FilmConstants<S> film = FilmConstants<S>::Published();
  film.c1 = S(0);
  film.c2 = S(-0.0);

  for (const S zero : {S(0.0), S(-0.0)}) {
    const SVector<S> out = ComputeS<S>(film, Vec3<S>(zero, -zero, zero));

    ExpectFlagged(out, DecodeStatus::kIndeterminate);
  }
}

TYPED_TEST(TactileDecodingTest, NonFiniteComponentIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const S specials[] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                        -std::numeric_limits<S>::infinity()};

  for (int axis = 0; axis < 3; ++axis) {
    for (const S special : specials) {
      Vec3<S> field = FieldMilliTesla<S>(1.0, -1.0, 4.0);
      field[axis] = special;

      const SVector<S> out = ComputeS<S>(film, field);

      ExpectFlagged(out, DecodeStatus::kNonFiniteInput);
    }
  }
}

TYPED_TEST(TactileDecodingTest, NonFiniteFilmConstantIsFlagged) {
  using S = TypeParam;
  FilmConstants<S> film = FilmConstants<S>::Published();
  film.c2 = std::numeric_limits<S>::quiet_NaN();

  const SVector<S> out = ComputeS<S>(film, FieldMilliTesla<S>(1.0, -1.0, 4.0));

  ExpectFlagged(out, DecodeStatus::kNonFiniteInput);
}

TYPED_TEST(TactileDecodingTest, MilliTeslaFedAsTeslaIsOutOfRange) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const Vec3<S> field_mt(S(1.2), S(-0.8), S(-4.5));  // a working-volume field, in mT

  const SVector<S> out = ComputeS<S>(film, field_mt);

  ExpectFlagged(out, DecodeStatus::kOutOfRange);
}

// Documented behaviour: a magnet mounted upside down is not detected; reversing every field
// component decodes exactly like the original field with the offsets c negated.
TYPED_TEST(TactileDecodingTest, FlippedMagnetDecodesLikeNegatedOffsets) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  FilmConstants<S> negated = film;
  negated.c1 = -film.c1;
  negated.c2 = -film.c2;
  const S tolerance = S(16) * std::numeric_limits<S>::epsilon();

  for (const double sign_z : {1.0, -1.0}) {
    for (const Vec3<S>& field :
         {FieldMilliTesla<S>(1.5, -0.7, 5.0 * sign_z), FieldMilliTesla<S>(-2.0, 2.0, 2.0 * sign_z),
          FieldMilliTesla<S>(0.3, 1.1, 8.0 * sign_z)}) {
      const SVector<S> flipped = ComputeS<S>(film, -field);
      const SVector<S> reference = ComputeS<S>(negated, field);

      ASSERT_TRUE(flipped.ok()) << DecodeStatusName(flipped.status);
      ASSERT_TRUE(reference.ok());
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(flipped.s[i], reference.s[i], tolerance * (S(1) + std::abs(reference.s[i])));
      }
    }
  }
}

TYPED_TEST(TactileDecodingTest, WorkingBoxCornersDecodeInsideThePrintedBranch) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();

  for (const double bz_sign : {1.0, -1.0}) {
    for (const double bx : {-kBoxTransverseMt, kBoxTransverseMt}) {
      for (const double by : {-kBoxTransverseMt, kBoxTransverseMt}) {
        for (const double bz : {kBoxBzMinMt, kBoxBzMaxMt}) {
          const SVector<S> out = ComputeS<S>(film, FieldMilliTesla<S>(bx, by, bz_sign * bz));
          const double bz1 = film.k1 * bz_sign * bz * 1e-3 + film.c1;

          ASSERT_TRUE(out.ok()) << DecodeStatusName(out.status);
          EXPECT_LT(std::abs(out.s.x()), S(std::numbers::pi / 2));
          EXPECT_LT(std::abs(out.s.y()), S(std::numbers::pi / 2));
          EXPECT_EQ(std::signbit(out.s.x()), std::signbit(bx * bz1));
          EXPECT_EQ(std::signbit(out.s.y()), std::signbit(by * bz1));
          EXPECT_TRUE(std::isfinite(out.s.z()));
        }
      }
    }
  }
}

TEST(TactileDecodingLiteralTest, AgreesWithThePrintedFormulasAtOrdinaryPoints) {
  const FilmConstants<double> film = FilmConstants<double>::Published();
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> transverse(-kBoxTransverseMt, kBoxTransverseMt);
  std::uniform_real_distribution<double> axial(kBoxBzMinMt, kBoxBzMaxMt);
  std::bernoulli_distribution negative_bz(0.5);

  for (int i = 0; i < 10000; ++i) {
    const Vec3<double> field = FieldMilliTesla<double>(
        transverse(rng), transverse(rng), (negative_bz(rng) ? -1.0 : 1.0) * axial(rng));

    const SVector<double> out = ComputeS<double>(film, field);
    const Vec3<double> literal = LiteralS(film, field);

    ASSERT_TRUE(out.ok());
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_NEAR(out.s[axis], literal[axis], 1e-12 * (1.0 + std::abs(literal[axis])))
          << axis << " at " << field.transpose();
    }
  }
}

TEST(TactileDecodingLiteralTest, FloatAndDoubleAgreeOverTheWorkingVolume) {
  const FilmConstants<float> film_f = FilmConstants<float>::Published();
  const FilmConstants<double> film_d = FilmConstants<double>::Published();
  double worst = 0.0;

  for (double bx = -kBoxTransverseMt; bx <= kBoxTransverseMt + 1e-9; bx += 0.125) {
    for (double by = -kBoxTransverseMt; by <= kBoxTransverseMt + 1e-9; by += 0.125) {
      for (double bz_abs = kBoxBzMinMt; bz_abs <= kBoxBzMaxMt + 1e-9; bz_abs += 0.25) {
        for (const double bz : {bz_abs, -bz_abs}) {
          const Vec3<float> field_f = FieldMilliTesla<float>(bx, by, bz);

          const SVector<float> out_f = ComputeS<float>(film_f, field_f);
          const SVector<double> out_d = ComputeS<double>(film_d, field_f.cast<double>());

          ASSERT_TRUE(out_f.ok());
          ASSERT_TRUE(out_d.ok());
          for (int axis = 0; axis < 3; ++axis) {
            const double error = std::abs(double(out_f.s[axis]) - out_d.s[axis]);
            ASSERT_LE(error, 1e-5 * std::abs(out_d.s[axis]))
                << axis << " at " << field_f.transpose();
            if (out_d.s[axis] != 0.0) worst = std::max(worst, error / std::abs(out_d.s[axis]));
          }
        }
      }
    }
  }
  RecordProperty("worst_relative_difference", ::testing::PrintToString(worst));
}

// Uniform fields over ±20 mT, plus magnitudes from underflow to overflow and special values:
// whatever comes in, an unflagged result is finite and a flagged one is exactly zero.
TYPED_TEST(TactileDecodingTest, RandomInputsNeverGiveUnflaggedNonFiniteOutput) {
  using S = TypeParam;
  using Limits = std::numeric_limits<S>;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  std::mt19937_64 rng(0x7ac711e);
  std::uniform_real_distribution<double> ordinary(-20e-3, 20e-3);
  std::uniform_real_distribution<double> exponent(Limits::min_exponent10 - 8.0,
                                                  Limits::max_exponent10 + 2.0);
  std::uniform_int_distribution<int> kind(0, 9);
  std::bernoulli_distribution negative(0.5);
  const S specials[] = {S(0.0),
                        S(-0.0),
                        Limits::quiet_NaN(),
                        Limits::infinity(),
                        -Limits::infinity(),
                        Limits::denorm_min(),
                        Limits::min(),
                        Limits::max(),
                        -Limits::max(),
                        S(1e-7),
                        S(-1e-7),
                        S(1),
                        S(-1),
                        std::nextafter(S(1), S(2)),
                        -film.c1 / film.k1,
                        -film.c2 / film.k2};
  std::uniform_int_distribution<std::size_t> pick(0, std::size(specials) - 1);
  const auto component = [&]() -> S {
    const int k = kind(rng);
    if (k < 8) return S(ordinary(rng));
    if (k == 8) {
      // Converting a double beyond the float range is undefined behaviour, so overflow explicitly.
      const double magnitude = std::pow(10.0, exponent(rng));
      const S value = magnitude > double(Limits::max()) ? Limits::infinity() : S(magnitude);
      return negative(rng) ? -value : value;
    }
    return specials[pick(rng)];
  };
  int ok_count = 0;

  for (int i = 0; i < 1000000; ++i) {
    const Vec3<S> field(component(), component(), component());

    const SVector<S> out = ComputeS<S>(film, field);

    if (out.ok()) {
      ++ok_count;
      ASSERT_TRUE(AllFinite(out.s)) << field.transpose();
      ASSERT_LE(std::abs(out.s.x()), S(std::numbers::pi)) << field.transpose();
      ASSERT_LE(std::abs(out.s.y()), S(std::numbers::pi)) << field.transpose();
    } else {
      ASSERT_EQ(out.s, Vec3<S>::Zero()) << field.transpose();
    }
  }
  EXPECT_GT(ok_count, 400000);  // most inputs are ordinary fields, which must decode
}

TYPED_TEST(TactileDecodingTest, DecodeForceIsCalibrationTimesSPlusOffset) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const ForceCalibration<S> calibration{Vec3<S>(S(2), S(-3), S(0.5)),
                                        Vec3<S>(S(0.1), S(0.2), S(3))};
  const Vec3<S> field = FieldMilliTesla<S>(0.8, -0.4, -5.0);

  const ForceResult<S> force = DecodeForce<S>(film, calibration, field);
  const SVector<S> s = ComputeS<S>(film, field);

  ASSERT_TRUE(force.ok());
  EXPECT_EQ(force.force_n, calibration.a.cwiseProduct(s.s) + calibration.b);
}

TYPED_TEST(TactileDecodingTest, DecodeForcePassesFlagsThroughWithZeroForce) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const ForceCalibration<S> calibration{Vec3<S>::Ones(), Vec3<S>(S(0.1), S(0.2), S(3))};

  const ForceResult<S> force =
      DecodeForce<S>(film, calibration, FieldMilliTesla<S>(3.0, 0, 4.0) * S(1e3));

  EXPECT_EQ(force.status, DecodeStatus::kOutOfRange);
  EXPECT_EQ(force.force_n, Vec3<S>::Zero());
}

TYPED_TEST(TactileDecodingTest, SaturatedReadingIsFlaggedSaturated) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const FieldReading<S> reading{FieldMilliTesla<S>(0.5, 0.5, 4.9), true, true};

  const SVector<S> out = ComputeS<S>(film, reading);

  ExpectFlagged(out, DecodeStatus::kSaturated);
}

TYPED_TEST(TactileDecodingTest, NonFiniteCalibrationIsFlagged) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const ForceCalibration<S> calibration{Vec3<S>::Ones(),
                                        Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN())};

  const ForceResult<S> force = DecodeForce<S>(film, calibration, FieldMilliTesla<S>(0.5, 0.5, 4.0));

  EXPECT_EQ(force.status, DecodeStatus::kNonFiniteInput);
  EXPECT_EQ(force.force_n, Vec3<S>::Zero());
}

TEST(DecodeStatusNameTest, NamesAreStableSnakeCase) {
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kOk), "ok");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kNonFiniteInput), "non_finite_input");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kSaturated), "saturated");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kBzPrimeSingular), "bz_prime_singular");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kBzDoublePrimeSingular), "bz_double_prime_singular");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kIndeterminate), "indeterminate");
  EXPECT_STREQ(DecodeStatusName(DecodeStatus::kOutOfRange), "out_of_range");
}

}  // namespace
}  // namespace hilrig::dut_fw
