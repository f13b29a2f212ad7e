// The list of models a run builds, with the fidelity of each, as the report states it: a reader of
// a report can tell exactly what was simulated and what was not.
#pragma once

#include "host/scenario/scenario_config.h"
#include "proto/report.pb.h"

namespace hilrig::host {

void AppendModelList(const ScenarioConfig& config, const std::string& dut_description,
                     proto::Report& report);

}  // namespace hilrig::host
