// Reading a spec written in protobuf text format (a scenario, a sweep): parse, validate, and report
// every problem as "file:line:column: field: message" (1-based line and column), pointing at the
// offending field, or at its enclosing message when a required field is missing, so an author can
// go straight to it. All problems of a file are reported at once, not just the first.
#pragma once

#include <google/protobuf/message.h>

#include <functional>
#include <string>
#include <vector>

#include "host/scenario/scenario_validation.h"
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

// The problems of a parsed spec, each under its field path ("timeline[3].pour.mass_kg").
using SpecValidator = std::function<std::vector<FieldProblem>(const google::protobuf::Message&)>;

// Parses `text`, which came from `file_label`, into `spec` and validates it; on failure the error
// lists every problem, one per line, located in the text.
rig::Result<void> ParseTextSpec(const std::string& text, const std::string& file_label,
                                google::protobuf::Message& spec, const SpecValidator& validate);

}  // namespace hilrig::host
