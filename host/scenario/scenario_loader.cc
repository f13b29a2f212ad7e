#include "host/scenario/scenario_loader.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "host/scenario/scenario_validation.h"
#include "rig/file_io.h"

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

struct PathPart {
  std::string field;
  int index = -1;  // -1 for a singular field
};

std::vector<PathPart> SplitPath(const std::string& path) {
  std::vector<PathPart> parts;
  std::stringstream stream(path);
  std::string token;
  while (std::getline(stream, token, '.')) {
    PathPart part;
    const auto bracket = token.find('[');
    part.field = token.substr(0, bracket);
    if (bracket != std::string::npos) part.index = std::stoi(token.substr(bracket + 1));
    parts.push_back(part);
  }
  return parts;
}

// The location of the deepest part of `path` that the text actually wrote: a field that was left
// out is reported at the message that should have held it.
TextFormat::ParseLocation Locate(const TextFormat::ParseInfoTree& root, const std::string& path) {
  const Descriptor* descriptor = proto::Scenario::descriptor();
  const TextFormat::ParseInfoTree* tree = &root;
  TextFormat::ParseLocation best;
  for (const PathPart& part : SplitPath(path)) {
    const FieldDescriptor* field = descriptor ? descriptor->FindFieldByName(part.field) : nullptr;
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

rig::Result<proto::Scenario> ParseScenario(const std::string& text, const std::string& file_label) {
  CollectingErrors errors(file_label);
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  TextFormat::ParseInfoTree locations;
  parser.WriteLocationsTo(&locations);
  proto::Scenario scenario;
  if (!parser.ParseFromString(text, &scenario)) {
    if (errors.problems().empty()) return rig::MakeError(file_label + ": cannot parse scenario");
    return rig::MakeError(JoinProblems(errors.problems()));
  }
  std::vector<SpecProblem> problems;
  for (const FieldProblem& problem : ValidateScenario(scenario)) {
    const TextFormat::ParseLocation where = Locate(locations, problem.field_path);
    problems.push_back(
        {file_label, where.line + 1, where.column + 1, problem.field_path, problem.message});
  }
  if (!problems.empty()) return rig::MakeError(JoinProblems(problems));
  return scenario;
}

rig::Result<proto::Scenario> LoadScenario(const std::string& path) {
  auto text = rig::ReadRegularFile(path, kMaxScenarioFileBytes);
  if (!text) return text.error();
  return ParseScenario(text.value(), path);
}

rig::Result<std::vector<std::string>> ScenarioFilesIn(const std::string& folder) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code error;
  // Only names are read: an entry's status could fail (a link loop) and is the loader's concern.
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end;
       entry.increment(error)) {
    if (entry->path().extension() == ".textproto") files.push_back(entry->path().string());
  }
  if (error) return rig::MakeError("cannot list folder " + folder + ": " + error.message());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace hilrig::host
