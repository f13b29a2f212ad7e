#include "host/trace/trace_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>

namespace hilrig::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TraceSample Sample() {
  TraceSample s;
  s.position_m = {3, 4, 1};
  s.reference_m = {0, 0, 3};
  s.velocity_m_s = {0, 0.6, 0.8};
  s.tilt_deg = 5;
  s.tactile_force_max_n = 1.5;
  s.tactile_force_error_max_n = 0.25;
  s.grasp_force_n = 2;
  s.grasp_force_estimate_n = 2.5;
  s.load_n = 4;
  s.load_estimate_n = 3;
  s.object_dropped = true;
  s.servo_angle_rad = 0.75;
  s.ground_force_n = 6.5;
  s.object_held = true;
  s.slip_speed_m_s = 0.02;
  s.pad_force_n = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  s.pad_force_estimate_n = {1.1, 1.2, 1.3, 1.4, 1.5, 1.6};
  s.pad_force_error_n = {2.1, 2.2, 2.3, 2.4, 2.5, 2.6};
  return s;
}

TEST(SignalValueTest, EverySignalReadsItsQuantity) {
  const TraceSample s = Sample();
  // Error (3, 4, -2): |e| = sqrt(29), horizontal 5, altitude 2.
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::POSITION_ERROR_M), std::sqrt(29.0));
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::HORIZONTAL_ERROR_M), 5.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::ALTITUDE_ERROR_M), 2.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::ALTITUDE_M), 1.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::TILT_DEG), 5.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::SPEED_M_S), 1.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::TACTILE_FORCE_N), 1.5);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::TACTILE_FORCE_ERROR_N), 0.25);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::GRASP_FORCE_N), 2.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::GRASP_FORCE_ESTIMATE_N), 2.5);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::GRASP_FORCE_ERROR_N), 0.5);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::LOAD_N), 4.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::LOAD_ESTIMATE_ERROR_N), 1.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::OBJECT_DAMAGED), 0.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::OBJECT_DROPPED), 1.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::SERVO_ANGLE_RAD), 0.75);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::GROUND_FORCE_N), 6.5);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::OBJECT_HELD), 1.0);
  EXPECT_DOUBLE_EQ(SignalValue(s, proto::SLIP_SPEED_M_S), 0.02);
  EXPECT_TRUE(std::isnan(SignalValue(s, proto::SIGNAL_UNSPECIFIED)));
  EXPECT_TRUE(std::isnan(SignalValue(s, static_cast<proto::Signal>(999))));
}

TEST(SignalValueTest, APadSignalReadsThePadItNames) {
  const TraceSample s = Sample();
  for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
    EXPECT_EQ(SignalValue(s, proto::PAD_FORCE_N, pad), s.pad_force_n[pad]);
    EXPECT_EQ(SignalValue(s, proto::PAD_FORCE_ESTIMATE_N, pad), s.pad_force_estimate_n[pad]);
    EXPECT_EQ(SignalValue(s, proto::PAD_FORCE_ERROR_N, pad), s.pad_force_error_n[pad]);
    EXPECT_EQ(SignalReaderFor(proto::PAD_FORCE_N, pad)(s), s.pad_force_n[pad]);
  }
  // Without a pad, or past the last one, a pad signal reads nothing.
  EXPECT_TRUE(std::isnan(SignalValue(s, proto::PAD_FORCE_N)));
  EXPECT_TRUE(std::isnan(SignalValue(s, proto::PAD_FORCE_ESTIMATE_N, kTracePadCount)));
  EXPECT_TRUE(IsPadSignal(proto::PAD_FORCE_ERROR_N));
  EXPECT_FALSE(IsPadSignal(proto::TACTILE_FORCE_N));
}

TEST(SignalValueTest, AReaderGivesWhatSignalValueGives) {
  const TraceSample s = Sample();
  const google::protobuf::EnumDescriptor* signals = proto::Signal_descriptor();
  for (int i = 0; i < signals->value_count(); ++i) {
    const auto signal = static_cast<proto::Signal>(signals->value(i)->number());
    const double expected = SignalValue(s, signal, 1);
    const double read = SignalReaderFor(signal, 1)(s);
    EXPECT_TRUE(read == expected || (std::isnan(read) && std::isnan(expected)))
        << signals->value(i)->name();
  }
}

// The definition AllSignalsFinite must keep: every signal of the enum (of every pad for the pads'
// signals), one by one.
bool EverySignalFinite(const TraceSample& sample) {
  const google::protobuf::EnumDescriptor* signals = proto::Signal_descriptor();
  for (int i = 0; i < signals->value_count(); ++i) {
    const auto signal = static_cast<proto::Signal>(signals->value(i)->number());
    if (signal == proto::SIGNAL_UNSPECIFIED) continue;
    const std::size_t pads = IsPadSignal(signal) ? kTracePadCount : 1;
    for (std::size_t pad = 0; pad < pads; ++pad) {
      const auto which = IsPadSignal(signal) ? std::optional<std::size_t>(pad) : std::nullopt;
      if (!std::isfinite(SignalValue(sample, signal, which))) return false;
    }
  }
  return true;
}

TEST(AllSignalsFiniteTest, AFiniteSampleIsFinite) { EXPECT_TRUE(AllSignalsFinite(Sample())); }

TEST(AllSignalsFiniteTest, NaNInAWatchedFieldIsFound) {
  TraceSample s = Sample();
  s.reference_m.y() = kNaN;
  EXPECT_FALSE(AllSignalsFinite(s));
  s = Sample();
  s.load_estimate_n = kInf;  // only the load estimate error reads it
  EXPECT_FALSE(AllSignalsFinite(s));
  s = Sample();
  s.velocity_m_s.x() = -kInf;
  EXPECT_FALSE(AllSignalsFinite(s));
}

TEST(AllSignalsFiniteTest, FieldsNoSignalReadsDoNotCount) {
  TraceSample s = Sample();
  s.time_s = kNaN;
  s.roll_pitch_yaw_deg = {kNaN, kNaN, kNaN};
  s.rotor_thrust_n[2] = kInf;
  s.estimated_position_m.x() = kNaN;
  s.grasp_force_setpoint_n = kNaN;
  s.grasp_settled_s = kInf;
  s.object_mass_kg = kNaN;
  s.servo_command_rad = kNaN;
  EXPECT_TRUE(AllSignalsFinite(s));
}

// Finite fields whose derived signal overflows: a norm of 1e200 m, a difference of two 1e308 N.
TEST(AllSignalsFiniteTest, OverflowInADerivedSignalCounts) {
  TraceSample s = Sample();
  s.position_m.x() = 1e200;
  EXPECT_FALSE(AllSignalsFinite(s));
  s = Sample();
  s.grasp_force_n = 1.7e308;
  s.grasp_force_estimate_n = -1.7e308;
  EXPECT_FALSE(AllSignalsFinite(s));
}

// Random samples whose fields are each finite, huge, infinite or NaN now and then: the answer is
// the signal-by-signal one every time.
TEST(AllSignalsFiniteTest, AgreesWithEverySignalOneByOne) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto field = [&] {
    switch (rng() % 100) {
      case 0:
        return kNaN;
      case 1:
        return kInf;
      case 2:
        return -kInf;
      case 3:
        return 1.5e308 * unit(rng);
      case 4:
        return 1e160 * unit(rng);
      default:
        return 10 * unit(rng);
    }
  };
  int non_finite = 0;
  for (int i = 0; i < 20000; ++i) {
    TraceSample s;
    s.position_m = {field(), field(), field()};
    s.reference_m = {field(), field(), field()};
    s.velocity_m_s = {field(), field(), field()};
    s.tilt_deg = field();
    s.tactile_force_max_n = field();
    s.tactile_force_error_max_n = field();
    s.grasp_force_n = field();
    s.grasp_force_estimate_n = field();
    s.load_n = field();
    s.load_estimate_n = field();
    s.servo_angle_rad = field();
    s.ground_force_n = field();
    s.slip_speed_m_s = field();
    s.pad_force_n[rng() % kTracePadCount] = field();
    s.pad_force_estimate_n[rng() % kTracePadCount] = field();
    s.pad_force_error_n[rng() % kTracePadCount] = field();
    s.object_damaged = rng() % 2 == 0;
    s.object_held = rng() % 2 == 0;
    const bool expected = EverySignalFinite(s);
    ASSERT_EQ(AllSignalsFinite(s), expected) << "sample " << i;
    non_finite += expected ? 0 : 1;
  }
  EXPECT_GT(non_finite, 1000);  // both answers were exercised
  EXPECT_LT(non_finite, 19000);
}

}  // namespace
}  // namespace hilrig::host
