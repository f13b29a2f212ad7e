#include "host/scenario/text_spec.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <sstream>

#include "host/scenario/field_path.h"

namespace hilrig::host {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::TextFormat;

class CollectingErrors final : public google::protobuf::io::ErrorCollector {
 public:
  explicit CollectingErrors(std::string file) : file_(std::move(file)) {}
  void AddError(int line, google::protobuf::io::ColumnNumber column,
                const std::string& message) override {
    problems_.push_back({file_, line + 1, static_cast<int>(column) + 1, "", message});
  }
  const std::vector<SpecProblem>& problems() const { return problems_; }

 private:
  std::string file_;
  std::vector<SpecProblem> problems_;
};

// The location of the deepest part of `path` that the text actually wrote: a field that was left
// out is reported at the message that should have held it.
TextFormat::ParseLocation Locate(const TextFormat::ParseInfoTree& root,
                                 const Descriptor* descriptor, const std::string& path) {
  const TextFormat::ParseInfoTree* tree = &root;
  TextFormat::ParseLocation best;
  const auto parts = ParseFieldPath(path);
  if (!parts.ok()) return best;  // a problem with the whole spec
  for (const FieldPathPart& part : parts.value()) {
    const FieldDescriptor* field = descriptor ? descriptor->FindFieldByName(part.name) : nullptr;
    if (field == nullptr || tree == nullptr) break;
    const TextFormat::ParseLocation here = tree->GetLocation(field, part.index);
    if (here.line < 0) break;
    best = here;
    tree = field->message_type() ? tree->GetTreeForNested(field, part.index) : nullptr;
    descriptor = field->message_type();
  }
  return best;
}

std::string JoinProblems(const std::vector<SpecProblem>& problems) {
  std::string joined;
  for (const SpecProblem& problem : problems) {
    if (!joined.empty()) joined += '\n';
    joined += problem.ToString();
  }
  return joined;
}

}  // namespace

std::string SpecProblem::ToString() const {
  std::ostringstream text;
  text << file;
  if (line > 0) text << ':' << line << ':' << column;
  text << ": ";
  if (!field.empty()) text << field << ": ";
  text << message;
  return text.str();
}

rig::Result<void> ParseTextSpec(const std::string& text, const std::string& file_label,
                                google::protobuf::Message& spec, const SpecValidator& validate) {
  CollectingErrors errors(file_label);
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  TextFormat::ParseInfoTree locations;
  parser.WriteLocationsTo(&locations);
  if (!parser.ParseFromString(text, &spec)) {
    if (errors.problems().empty()) {
      return rig::MakeError(file_label + ": cannot parse " + spec.GetDescriptor()->name());
    }
    return rig::MakeError(JoinProblems(errors.problems()));
  }
  std::vector<SpecProblem> problems;
  for (const FieldProblem& problem : validate(spec)) {
    const TextFormat::ParseLocation where =
        Locate(locations, spec.GetDescriptor(), problem.field_path);
    problems.push_back(
        {file_label, where.line + 1, where.column + 1, problem.field_path, problem.message});
  }
  if (!problems.empty()) return rig::MakeError(JoinProblems(problems));
  return {};
}

}  // namespace hilrig::host
