// Loads a scenario spec from protobuf text format and validates it before anything runs; every
// problem is reported at once, located in the file (host/scenario/text_spec.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "host/scenario/text_spec.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// The largest spec file read: a shipped spec is a few KB, so 16 MiB leaves room for generated
// timelines while `/dev/zero` or a mistyped path to a data file is refused at once.
inline constexpr std::size_t kMaxScenarioFileBytes = std::size_t{16} << 20;

// Reads (a regular file, at most kMaxScenarioFileBytes), parses and validates; on failure the error
// message lists every problem, one per line.
rig::Result<proto::Scenario> LoadScenario(const std::string& path);

// Every entry directly in `folder` named *.textproto, sorted. Whatever such an entry is (a file, a
// folder, a dangling or looping link) it is listed, so that loading it says what is wrong rather
// than the scenario being skipped in silence; other entries are never looked at. Fails, naming
// the folder and the cause, when the folder cannot be listed.
rig::Result<std::vector<std::string>> ScenarioFilesIn(const std::string& folder);

// Parses and validates text that came from `file_label`; for tests and for `hilrig check`.
rig::Result<proto::Scenario> ParseScenario(const std::string& text, const std::string& file_label);

}  // namespace hilrig::host
