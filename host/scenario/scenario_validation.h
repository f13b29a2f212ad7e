// Semantic checks of a parsed scenario spec: physical parameters in range, rates that divide the
// physics rate, envelopes with bounds, a timeline inside the run. Each problem is named by its
// field path ("vehicle.mass_kg", "envelopes[2].upper"), which the loader turns into a location.
#pragma once

#include <string>
#include <vector>

#include "proto/scenario.pb.h"

namespace hilrig::host {

struct FieldProblem {
  std::string field_path;  // dotted path with [index] for repeated fields
  std::string message;
};

std::vector<FieldProblem> ValidateScenario(const proto::Scenario& scenario);

}  // namespace hilrig::host
