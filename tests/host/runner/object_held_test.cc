// "Not dropped" passes for an egg that never left its stand; OBJECT_HELD says whether the object
// is off its stand and in the pads. An egg gripped at 3 N on its stand and never lifted off it
// fails a "held" envelope while passing "not dropped"; with the stand taken away after the grasp
// it is held; gripped at 1.2 N it slides along the pads (SLIP_SPEED_M_S) and falls out.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/scene_text_run.h"

namespace hilrig::host {
namespace {

const proto::EnvelopeResult* Envelope(const proto::Report& report, const std::string& name) {
  return EnvelopeNamed(report, name);
}

proto::Report RunEgg(const std::string& grasp_n, const std::string& timeline) {
  const std::string text = R"(name: "egg_held"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" } }
object { fixture: "egg" }
simulation { duration_s: 5 }
timeline { at_s: 1 grasp { force_n: )" +
                           grasp_n + R"( } }
)" + timeline + R"(
envelopes { name: "held" signal: OBJECT_HELD lower: 1 from_s: 4 }
envelopes { name: "not_dropped" signal: OBJECT_DROPPED upper: 0 }
envelopes { name: "slip" signal: SLIP_SPEED_M_S upper: 1e9 }
)";
  return RunSceneText(text, "egg_held.textproto");
}

TEST(ObjectHeldTest, AnEggLeftOnItsStandIsNotHeldThoughNotDropped) {
  const proto::Report left = RunEgg("3", "");
  ASSERT_NE(Envelope(left, "held"), nullptr);
  EXPECT_EQ(Envelope(left, "held")->verdict(), proto::FAIL);
  EXPECT_EQ(Envelope(left, "held")->worst_value(), 0);
  EXPECT_EQ(Envelope(left, "not_dropped")->verdict(), proto::PASS);
  EXPECT_EQ(Envelope(left, "slip")->worst_value(), 0);  // never in the pads off its stand

  const proto::Report lifted = RunEgg("3", "timeline { at_s: 3 remove_support {} }");
  EXPECT_EQ(Envelope(lifted, "held")->verdict(), proto::PASS);
  EXPECT_EQ(Envelope(lifted, "held")->worst_value(), 1);
  EXPECT_EQ(Envelope(lifted, "not_dropped")->verdict(), proto::PASS);
  EXPECT_EQ(Envelope(lifted, "slip")->worst_value(), 0);  // static friction carries it

  // At 1.2 N friction cannot carry the egg: it slides along the pads, then falls out.
  const proto::Report weak = RunEgg("1.2", "timeline { at_s: 3 remove_support {} }");
  EXPECT_EQ(Envelope(weak, "held")->verdict(), proto::FAIL);
  EXPECT_EQ(Envelope(weak, "not_dropped")->verdict(), proto::FAIL);
  EXPECT_GT(Envelope(weak, "slip")->worst_value(), 0.01);
}

}  // namespace
}  // namespace hilrig::host
