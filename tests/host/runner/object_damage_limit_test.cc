// An egg cracks at 25 N a pad, and the servo squeezes at most 1.7 N a pad: "must not crack" could
// never fail. A lab's own egg gets its limit in the spec (object.damage_force_n), and the report
// says each object's limit and how far its peak force stayed below it.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/scene_text_run.h"

namespace hilrig::host {
namespace {

proto::Report SqueezeEgg(const std::string& object_extra) {
  const std::string text = R"(name: "egg_limit"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" } }
object { fixture: "egg" )" +
                           object_extra + R"( }
simulation { duration_s: 4 }
timeline { at_s: 1 grasp { force_n: 6 } }
envelopes { name: "not_cracked" signal: OBJECT_DAMAGED upper: 0 }
)";
  return RunSceneText(text, "egg_limit.textproto");
}

TEST(ObjectDamageLimitTest, ASpecsOwnLimitCracksTheEggWhereTheFixturesCannot) {
  const proto::Report fixture = SqueezeEgg("");
  ASSERT_EQ(fixture.objects_size(), 1);
  EXPECT_EQ(fixture.objects(0).damage(), "none");
  EXPECT_EQ(fixture.objects(0).damage_force_n(), 25);
  EXPECT_NEAR(fixture.objects(0).damage_margin_n(), 25 - fixture.objects(0).peak_normal_force_n(),
              1e-12);
  EXPECT_GT(fixture.objects(0).peak_normal_force_n(), 0.5);  // 6 N over six pads, about 1 N each

  const proto::Report own = SqueezeEgg("damage_force_n: 0.5");
  ASSERT_EQ(own.objects_size(), 1);
  EXPECT_EQ(own.objects(0).damage(), "crack");
  EXPECT_EQ(own.objects(0).damage_force_n(), 0.5);
  EXPECT_LE(own.objects(0).damage_margin_n(), 0);
  EXPECT_FALSE(own.passed());
}

}  // namespace
}  // namespace hilrig::host
