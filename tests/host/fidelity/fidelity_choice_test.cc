#include "host/fidelity/fidelity_choice.h"

#include <gtest/gtest.h>

#include <string>

#include "host/scenario/scenario_loader.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

TEST(FidelityTest, WithFidelitySetsEveryChoiceInTheSpec) {
  proto::Scenario spec;
  const FidelityChoice reference = ReferenceFidelity(/*quick=*/false);

  const proto::Scenario changed = WithFidelity(spec, reference);

  EXPECT_EQ(changed.models().integrator(), proto::INTEGRATOR_DORMAND_PRINCE);
  EXPECT_EQ(changed.models().integrator_tolerance(), 1e-10);
  EXPECT_EQ(changed.simulation().plant_substeps(), 8u);
  EXPECT_EQ(changed.models().tactile().field_fidelity(), "tiles:64");
}

TEST(FidelityTest, SceneFidelityFillsTheResolverDefaults) {
  const FidelityChoice scene = SceneFidelity(proto::Scenario());

  EXPECT_EQ(scene.integrator, proto::INTEGRATOR_RK4);
  EXPECT_EQ(scene.plant_substeps, 1);
  EXPECT_EQ(scene.field_fidelity, "tiles:32");
  EXPECT_FALSE(scene.integrator_tolerance.has_value());
}

TEST(FidelityTest, TruncatedToDropsTimelineEntriesAfterTheEnd) {
  auto spec =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/balloon_grasp.textproto");
  ASSERT_TRUE(spec.ok());

  const proto::Scenario cut = TruncatedTo(spec.value(), 8);

  EXPECT_EQ(cut.simulation().duration_s(), 8);
  ASSERT_EQ(cut.timeline_size(), 2);  // the grasp at 1.5 s and the setpoint at 7 s
  EXPECT_EQ(cut.timeline(1).at_s(), 7);
}

// Every envelope stays, those that open after the cut included: their report then says they were
// not evaluated instead of leaving them out of the verdict.
TEST(FidelityTest, TruncatedToKeepsEveryEnvelope) {
  auto spec = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/load_ramp.textproto");
  ASSERT_TRUE(spec.ok());

  const proto::Scenario cut = TruncatedTo(spec.value(), 18);

  ASSERT_EQ(cut.envelopes_size(), spec.value().envelopes_size());
  for (int i = 0; i < cut.envelopes_size(); ++i) {
    EXPECT_EQ(cut.envelopes(i).name(), spec.value().envelopes(i).name());
  }
}

}  // namespace
}  // namespace hilrig::host
