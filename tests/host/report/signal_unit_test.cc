#include "host/report/signal_unit.h"

#include <gtest/gtest.h>

#include <string>

namespace hilrig::host {
namespace {

TEST(SignalUnitTest, EachSignalHasTheUnitItsNameEndsIn) {
  EXPECT_EQ(std::string(SignalUnit(proto::ALTITUDE_ERROR_M)), "m");
  EXPECT_EQ(std::string(SignalUnit(proto::TILT_DEG)), "deg");
  EXPECT_EQ(std::string(SignalUnit(proto::SPEED_M_S)), "m/s");
  EXPECT_EQ(std::string(SignalUnit(proto::SLIP_SPEED_M_S)), "m/s");
  EXPECT_EQ(std::string(SignalUnit(proto::OBJECT_HELD)), "");
  EXPECT_EQ(std::string(SignalUnit(proto::GRASP_FORCE_N)), "N");
  EXPECT_EQ(std::string(SignalUnit(proto::SERVO_ANGLE_RAD)), "rad");
  EXPECT_EQ(std::string(SignalUnit(proto::GROUND_FORCE_N)), "N");
  EXPECT_EQ(std::string(SignalUnit(proto::OBJECT_DROPPED)), "");
}

// A signal added to the proto without a unit here shows its numbers bare: every signal whose name
// ends in a unit must map to it.
TEST(SignalUnitTest, EverySignalWithAUnitSuffixHasThatUnit) {
  const auto* descriptor = proto::Signal_descriptor();
  for (int i = 0; i < descriptor->value_count(); ++i) {
    const std::string name = descriptor->value(i)->name();
    const auto signal = static_cast<proto::Signal>(descriptor->value(i)->number());
    const std::string unit = SignalUnit(signal);
    if (name.ends_with("_M_S")) {
      EXPECT_EQ(unit, "m/s") << name;
    } else if (name.ends_with("_M")) {
      EXPECT_EQ(unit, "m") << name;
    } else if (name.ends_with("_N")) {
      EXPECT_EQ(unit, "N") << name;
    } else if (name.ends_with("_DEG")) {
      EXPECT_EQ(unit, "deg") << name;
    } else if (name.ends_with("_RAD")) {
      EXPECT_EQ(unit, "rad") << name;
    } else {
      EXPECT_EQ(unit, "") << name;
    }
  }
}

}  // namespace
}  // namespace hilrig::host
