// Loads a scenario spec from protobuf text format and validates it before anything runs. Every
// problem is reported as "file:line:column: field: message" (1-based line and column), pointing at
// the offending field, or at its enclosing message when a required field is missing, so a scenario
// author can go straight to it. All problems of a file are reported at once, not just the first.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct SpecProblem {
  std::string file;
  int line = 0;    // 1-based; 0 when unknown
  int column = 0;  // 1-based; 0 when unknown
  std::string field;
  std::string message;

  std::string ToString() const;
};

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
