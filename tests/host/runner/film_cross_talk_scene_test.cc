// The films' fields on each other and on the reference magnetometer, in a grasp (the balloon,
// 0.6 N). Closing the frame moves the six films toward each other and toward the frame's axis: a
// reference 20 mm above the ring reads tens of uT more than Earth's field, which the DUT's
// geomagnetic compensation subtracts from every pad; on its 150 mm mast it reads well under 1 uT
// of them. The other five films' field at each chip stays, and biases every pad the same way.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/scene_text_run.h"

namespace hilrig::host {
namespace {

proto::Report RunBalloon(const std::string& tactile_extra) {
  const std::string text = R"(name: "cross_talk"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" zeroing_s: 1 )" +
                           tactile_extra + R"( } }
object { fixture: "balloon" }
simulation { duration_s: 8 }
timeline { at_s: 1.5 grasp { force_n: 0.6 } }
envelopes { name: "pad_force_error" signal: TACTILE_FORCE_ERROR_N upper: 0.05 from_s: 5 }
envelopes { name: "grasp_estimate" signal: GRASP_FORCE_ERROR_N upper: 0.05 from_s: 5 }
)";
  return RunSceneText(text, "cross_talk.textproto");
}

double Worst(const proto::Report& report, const std::string& envelope) {
  for (const auto& result : report.envelopes()) {
    if (result.name() == envelope) return result.worst_value();
  }
  ADD_FAILURE() << "no envelope " << envelope;
  return -1;
}

TEST(FilmCrossTalkSceneTest, AReferenceTooCloseToTheRingShowsInEveryPad) {
  const proto::Report none = RunBalloon("");
  const proto::Report on_mast = RunBalloon("film_cross_talk: true");
  const proto::Report too_close =
      RunBalloon("film_cross_talk: true reference_position_m { z: 0.02 }");
  // Without the films' fields on each other the DUT reads each pad within its budget.
  EXPECT_LT(Worst(none, "pad_force_error"), 0.03);
  EXPECT_LT(Worst(none, "grasp_estimate"), 0.05);
  // On the mast the reference is nearly clean; what is left is the other films at each chip.
  EXPECT_LT(Worst(on_mast, "pad_force_error"), 0.06);
  EXPECT_GT(Worst(on_mast, "pad_force_error"), Worst(none, "pad_force_error"));
  // The six pads' biases add up in the grasp force estimate.
  EXPECT_GT(Worst(on_mast, "grasp_estimate"), 0.1);
  // 20 mm above the ring the compensation subtracts the films' field from every pad.
  EXPECT_GT(Worst(too_close, "pad_force_error"), 0.15);
  EXPECT_GT(Worst(too_close, "pad_force_error"), 3 * Worst(on_mast, "pad_force_error"));
}

}  // namespace
}  // namespace hilrig::host
