// Each pad's truth in the envelopes: an egg gripped at 3 N presses each of the six pads with about
// a sixth of it, the DUT decodes each pad within a few hundredths of a newton, and an envelope on
// one pad fails when that pad's force leaves its bounds.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/scene_text_run.h"

namespace hilrig::host {
namespace {

const proto::EnvelopeResult* Envelope(const proto::Report& report, const std::string& name) {
  return EnvelopeNamed(report, name);
}

TEST(PadForceSignalTest, EachPadsTrueAndDecodedForceIsWatched) {
  const proto::Report report = RunSceneText(R"(name: "egg_pads"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" } }
object { fixture: "egg" }
simulation { duration_s: 4 }
timeline { at_s: 1 grasp { force_n: 3 } }
envelopes { name: "pad0_true" signal: PAD_FORCE_N pad: 0 lower: 0.3 upper: 0.7 from_s: 3 }
envelopes { name: "pad5_decoded" signal: PAD_FORCE_ESTIMATE_N pad: 5 lower: 0.3 upper: 0.7 from_s: 3 }
envelopes { name: "pad3_error" signal: PAD_FORCE_ERROR_N pad: 3 upper: 0.05 from_s: 3 }
envelopes { name: "pad2_light" signal: PAD_FORCE_N pad: 2 upper: 0.1 from_s: 3 }
envelopes { name: "pad2_before" signal: PAD_FORCE_N pad: 2 upper: 0 until_s: 0.9 }
)",
                                            "egg_pads.textproto");
  for (const char* name : {"pad0_true", "pad5_decoded", "pad3_error", "pad2_before"}) {
    ASSERT_NE(Envelope(report, name), nullptr);
    EXPECT_EQ(Envelope(report, name)->verdict(), proto::PASS) << name;
  }
  // 3 N over six pads: 0.5 N each, which a 0.1 N bound on one pad cannot hold.
  EXPECT_EQ(Envelope(report, "pad2_light")->verdict(), proto::FAIL);
  EXPECT_NEAR(Envelope(report, "pad2_light")->worst_value(), 0.5, 0.1);
  EXPECT_GT(Envelope(report, "pad3_error")->worst_value(), 0);  // the decoder is not exact
}

}  // namespace
}  // namespace hilrig::host
