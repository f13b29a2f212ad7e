// The events of a scene's timeline as short labels in time order (set-points, gusts, grasp
// commands, pours, hand-overs, stray fields): what a plot of the run marks so that a reader sees
// what the rig did when, beside what the vehicle did.
#pragma once

#include <string>
#include <vector>

#include "host/scenario/scenario_config.h"

namespace hilrig::host {

struct TimelineEvent {
  double at_s = 0;
  std::string label;  // e.g. "grasp 0.6 N", "gust 2 N for 0.5 s", "setpoint (0, 0, 1.2) m"
};

// Every event of `config`'s timeline, ordered by time (equal times keep the order above). Never
// fails.
std::vector<TimelineEvent> TimelineEvents(const ScenarioConfig& config);

}  // namespace hilrig::host
