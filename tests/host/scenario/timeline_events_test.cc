// The timeline's events as plot markers: every kind with its label, in time order.
#include "host/scenario/timeline_events.h"

#include <gtest/gtest.h>

#include <optional>

#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

std::vector<TimelineEvent> EventsOf(const std::string& text) {
  const auto spec = ParseScenario(text, "events.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  if (!spec.ok()) return {};
  return TimelineEvents(ResolveScenario(spec.value(), std::nullopt));
}

TEST(TimelineEventsTest, EveryKindIsLabelledInTimeOrder) {
  const auto events = EventsOf(R"(name: "events"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true } }
object { fixture: "water_bottle" }
simulation { duration_s: 20 }
timeline { at_s: 9 pour { mass_kg: 0.05 duration_s: 2 } }
timeline { at_s: 1.5 grasp { force_n: 3.5 } }
timeline { at_s: 6 remove_support {} }
timeline { at_s: 4 setpoint { position_m { x: 0.1 z: 0.6 } transition_s: 1 } }
timeline { at_s: 5 disturbance { force_world_n { x: 3 y: 4 } duration_s: 0.5 } }
timeline { at_s: 12 grasp { open: true } }
timeline { at_s: 14 present_object { fixture: "egg" } }
timeline { at_s: 16 stray_field { node: 3 field_sensor_t { x: 1e-4 } duration_s: 1 } }
)");
  const std::vector<std::pair<double, std::string>> expected = {
      {1.5, "grasp 3.5 N"}, {4, "setpoint (0.1, 0, 0.6) m"}, {5, "gust 5 N for 0.5 s"},
      {6, "stand removed"}, {9, "pour 50 g over 2 s"},       {12, "open"},
      {14, "present egg"},  {16, "stray field at node 3"}};
  ASSERT_EQ(events.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(events[i].at_s, expected[i].first) << i;
    EXPECT_EQ(events[i].label, expected[i].second) << i;
  }
}

TEST(TimelineEventsTest, AHoverHasNone) {
  EXPECT_TRUE(EventsOf("name: \"hover\"\nsimulation { duration_s: 1 }\n").empty());
}

}  // namespace
}  // namespace hilrig::host
