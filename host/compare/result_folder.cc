#include "host/compare/result_folder.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "host/report/report_files.h"

namespace hilrig::host {
namespace {

constexpr const char* kReportFile = "report.json";
constexpr const char* kSummaryFile = "summary.json";

std::string InFolder(const std::string& dir, const char* file) {
  return (std::filesystem::path(dir) / file).string();
}

template <typename Message>
rig::Result<Message> ReadMessage(const std::string& path) {
  Message message;
  if (auto read = ReadJsonFile(path, message); !read) return read.error();
  return message;
}

}  // namespace

rig::Result<ResultFolderKind> ResultFolderKindOf(const std::string& dir) {
  std::error_code error;
  if (!std::filesystem::is_directory(dir, error)) {
    return rig::MakeError(dir + " is not a folder");
  }
  if (std::filesystem::exists(InFolder(dir, kSummaryFile), error)) return ResultFolderKind::kSweep;
  if (std::filesystem::exists(InFolder(dir, kReportFile), error)) return ResultFolderKind::kRun;
  auto runs = SuiteRunNames(dir);
  if (runs && !runs.value().empty()) return ResultFolderKind::kSuite;
  return rig::MakeError(dir + " holds neither a run's " + kReportFile + ", a sweep's " +
                        kSummaryFile + " nor run folders of a folder run");
}

rig::Result<std::vector<std::string>> SuiteRunNames(const std::string& dir) {
  std::error_code error;
  std::filesystem::directory_iterator entries(dir, error);
  if (error) return rig::MakeError("cannot list " + dir + ": " + error.message());
  std::vector<std::string> names;
  for (const std::filesystem::directory_entry& entry : entries) {
    if (!entry.is_directory(error)) continue;
    if (std::filesystem::is_regular_file(entry.path() / kReportFile, error)) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

rig::Result<proto::Report> ReadRunReport(const std::string& dir) {
  return ReadMessage<proto::Report>(InFolder(dir, kReportFile));
}

rig::Result<proto::SweepSummary> ReadSweepSummary(const std::string& dir) {
  return ReadMessage<proto::SweepSummary>(InFolder(dir, kSummaryFile));
}

std::string RunTracePath(const std::string& dir) { return InFolder(dir, "trace.csv"); }

}  // namespace hilrig::host
