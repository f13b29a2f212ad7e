// A run's work per tick does not grow with the timeline: a spec with thousands of timeline entries
// of every kind runs with each entry (or piece of a schedule built from them) stepped over at most
// once in the whole run, where a scan of the timeline at every tick looks at ticks x entries.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

// Entries per kind: setpoints, disturbances, grasps (open), pours, stray fields at the reference
// node, objects presented and stands taken away, spread over a 1 s run (1000 ticks). The tactile
// pads stay off, so the scene needs no calibration.
constexpr int kPerKind = 2000;
constexpr int kKinds = 7;

std::string ManyEventsSpec() {
  std::string text = R"(name: "many_events"
vehicle { initial_position_m { z: 0.5 } }
object { fixture: "balloon" }
simulation { duration_s: 1 }
)";
  const char* actions[kKinds] = {
      "setpoint { position_m { z: 0.5 } transition_s: 0.01 }",
      "disturbance { force_world_n { x: 0.001 } duration_s: 0.01 }",
      "grasp { open: true }",
      "pour { mass_kg: 0.000001 duration_s: 0.01 }",
      "stray_field { node: 7 field_sensor_t { x: 1e-6 } duration_s: 0.01 }",
      "present_object { fixture: \"egg\" }",
      "remove_support {}",
  };
  for (int i = 0; i < kPerKind * kKinds; ++i) {
    const double at_s = static_cast<double>(i) / (kPerKind * kKinds);
    text += "timeline { at_s: " + std::to_string(at_s) + " " + actions[i % kKinds] + " }\n";
  }
  return text;
}

TEST(TimelineScaleTest, EachTimelineEntryIsSteppedOverOnceNotOncePerTick) {
  const auto spec = ParseScenario(ManyEventsSpec(), "many_events.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  const rig::SimClock wall_clock;
  ScenarioRunner runner(config, {}, {.wall_clock = &wall_clock});
  std::uint64_t ticks = 0;
  std::uint64_t stepped_at_half = 0;
  while (runner.Tick()) {
    if (++ticks == 500) stepped_at_half = runner.timeline_entries_stepped();
  }
  const proto::Report report = runner.Finish();
  ASSERT_EQ(report.stop_reason(), "completed");
  ASSERT_EQ(report.ticks(), 1000u);
  // The interval kinds (disturbances, pours, stray fields) give at most two pieces per entry, the
  // others one step per entry; the initial object counts too.
  const std::uint64_t bound = 2 * 3 * kPerKind + 3 * kPerKind + 1;
  const std::uint64_t stepped = runner.timeline_entries_stepped();
  EXPECT_LE(stepped, bound);
  // Work follows the entries passed, not the ticks: half the run steps over about half of them.
  EXPECT_GT(stepped_at_half, stepped / 3);
  EXPECT_LT(stepped_at_half, 2 * stepped / 3);
}

}  // namespace
}  // namespace hilrig::host
