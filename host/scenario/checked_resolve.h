// A spec resolved the way every run resolves it, its problems as errors instead of aborts: the
// spec validated (an error names the scene, the field and the cause) and its film's fidelity
// parsed (not built: building the field map is the setup's, which caches it).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "host/scenario/scenario_config.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// `spec` validated, its field fidelity parsed, then resolved with `seed` replacing the spec's and
// relative file names taken from `spec_directory`. Fails on the spec's first problem.
rig::Result<ScenarioConfig> ResolveChecked(const proto::Scenario& spec,
                                           const std::string& spec_directory,
                                           std::optional<std::uint64_t> seed);

}  // namespace hilrig::host
