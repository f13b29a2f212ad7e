// One number of a spec, set by its path from the spec's root in text-format names
// ("vehicle.mass_kg", "models.vio.latency_s", "timeline[2].grasp.force_n"): how a sweep's axes
// vary a scenario. A path that does not name a number the spec can hold is refused with the part
// that is wrong, before anything changes, so a sweep can check its axes against each scenario
// when it loads and never run a case that sets the wrong thing.
#pragma once

#include <google/protobuf/message.h>

#include <string>
#include <vector>

#include "rig/result.h"

namespace hilrig::host {

struct FieldPathPart {
  std::string name;
  int index = -1;  // an element of a repeated field; -1 for a singular field
};

// Splits "a.b[2].c"; an empty part, a bad or negative index or characters outside a field name
// ([A-Za-z0-9_]) are errors that quote the path.
rig::Result<std::vector<FieldPathPart>> ParseFieldPath(const std::string& path);

// Checks that `path` names a number field of `message` that `value` fits, and sets it; on an
// error nothing changes. The path must lead through singular message fields (an unset one is
// created, as the text format would) or existing elements of repeated ones, never through a
// oneof member while another member of that oneof is set (timeline[2].grasp on a setpoint
// entry). The last part must be a floating-point field (any finite value), an integer one (a whole
// value in its range), an enum (one of its numbers) or a bool (0 or 1).
rig::Result<void> SetNumberAt(google::protobuf::Message& message, const std::string& path,
                              double value);

// The check SetNumberAt makes, without a value: `path` names a number field `message` can reach.
rig::Result<void> CheckNumberPath(const google::protobuf::Message& message,
                                  const std::string& path);

}  // namespace hilrig::host
