#include "host/scenario/scenario_loader.h"

#include <algorithm>
#include <filesystem>

#include "host/scenario/scenario_validation.h"
#include "host/scenario/text_spec.h"
#include "rig/file_io.h"

namespace hilrig::host {

rig::Result<proto::Scenario> ParseScenario(const std::string& text, const std::string& file_label) {
  proto::Scenario scenario;
  auto parsed =
      ParseTextSpec(text, file_label, scenario, [](const google::protobuf::Message& spec) {
        return ValidateScenario(static_cast<const proto::Scenario&>(spec));
      });
  if (!parsed.ok()) return parsed.error();
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
