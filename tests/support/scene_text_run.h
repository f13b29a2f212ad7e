// Runs a scene written out in a test: the spec text parsed and resolved, its tactile sensors
// calibrated at its own field level, and the run stepped in lockstep on a simulated clock, with no
// files written, and its envelopes looked up by name. A spec that does not parse or calibrate fails
// the calling test.
#pragma once

#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "rig/clock.h"

namespace hilrig::host {

// The report of the scene `text`; `file_label` names it in parse errors.
inline proto::Report RunSceneText(const std::string& text, const std::string& file_label) {
  const auto spec = ParseScenario(text, file_label);
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  if (!spec.ok()) return {};
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  EXPECT_TRUE(LoadTactileCalibration(config).ok());
  const rig::SimClock wall_clock;
  return RunScenario(config, {}, {.wall_clock = &wall_clock});
}

// The result of the envelope `name` in `report`; null (and a failure of the calling test) when
// the report has none.
inline const proto::EnvelopeResult* EnvelopeNamed(const proto::Report& report,
                                                  const std::string& name) {
  for (const auto& envelope : report.envelopes()) {
    if (envelope.name() == name) return &envelope;
  }
  ADD_FAILURE() << "no envelope " << name;
  return nullptr;
}

}  // namespace hilrig::host
