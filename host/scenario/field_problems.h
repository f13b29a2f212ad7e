// How the scenario validation names what it refuses: a ProblemList collects problems under a
// field path ("timeline[3].pour.mass_kg") that the loader turns into a file location, and
// CheckEveryScalar applies one check to every set scalar of a message and of the messages it holds.
#pragma once

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/scenario/scenario_validation.h"

namespace hilrig::host {

// Collects problems under a path prefix, so each check names fields relative to its message.
class ProblemList {
 public:
  explicit ProblemList(std::vector<FieldProblem>& problems, std::string prefix = "")
      : problems_(problems), prefix_(std::move(prefix)) {}

  ProblemList Nested(const std::string& field) const { return ProblemList(problems_, Join(field)); }
  ProblemList Element(const std::string& field, int index) const {
    return ProblemList(problems_, Join(field) + "[" + std::to_string(index) + "]");
  }
  void Add(const std::string& field, std::string message) const {
    problems_.push_back({Join(field), std::move(message)});
  }
  // A problem with the message this list is about, not one of its fields.
  void AddHere(std::string message) const { problems_.push_back({prefix_, std::move(message)}); }

 private:
  std::string Join(const std::string& field) const {
    return prefix_.empty() ? field : prefix_ + "." + field;
  }
  std::vector<FieldProblem>& problems_;
  std::string prefix_;
};

// The problem with one scalar of `message`: element `index` of a repeated field, or the singular
// field's value when `index` is -1. Nothing when it is fine.
using ScalarCheck = std::function<std::optional<std::string>(
    const google::protobuf::Message& message, const google::protobuf::FieldDescriptor* field,
    int index)>;

// Runs `check` on every set scalar field of `message` and, recursively, of its message fields,
// adding each problem at the field (or repeated element) it is about.
void CheckEveryScalar(const google::protobuf::Message& message, const ProblemList& problems,
                      const ScalarCheck& check);

}  // namespace hilrig::host
