#include "host/report/run_folder.h"

#include <filesystem>
#include <iterator>
#include <vector>

#include "host/report/report_files.h"
#include "host/report/run_page.h"
#include "host/report/run_plots.h"
#include "host/report/stop_reason.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// A DUT's link log a previous run left (a MAVLink DUT's telemetry log).
constexpr const char* kDutLogFiles[] = {"mavlink.tlog"};

// The plots and link logs a previous run left: they would stand beside the new run's report as if
// it had made them.
rig::Result<void> RemoveOldFiles(const fs::path& out_dir) {
  std::vector<const char*> files(std::begin(kRunPlotFiles), std::end(kRunPlotFiles));
  files.insert(files.end(), std::begin(kDutLogFiles), std::end(kDutLogFiles));
  for (const char* file : files) {
    std::error_code error;
    fs::remove(out_dir / file, error);
    if (error)
      return rig::MakeError("cannot remove " + (out_dir / file).string() + ": " + error.message());
  }
  return {};
}

}  // namespace

rig::Result<void> WriteReportFiles(const proto::Report& report, const std::string& out_dir) {
  if (auto written = WriteJunitXml(report, (fs::path(out_dir) / "junit.xml").string()); !written) {
    return written.error();
  }
  if (auto written = WriteJsonFile(report, (fs::path(out_dir) / "report.json").string());
      !written) {
    return written.error();
  }
  return WriteRunPage(report, out_dir);
}

rig::Result<RunOutputFolder> RunOutputFolder::Claim(const std::string& out_dir,
                                                    const std::string& scenario,
                                                    const std::string& spec_file) {
  auto lock = rig::FolderLock::Acquire(out_dir);
  if (!lock) return lock.error();
  proto::Report incomplete;
  incomplete.set_scenario(scenario);
  incomplete.set_spec_file(spec_file);
  incomplete.set_passed(false);
  SetStop({StopReason::kIncomplete, {}}, incomplete);
  if (auto written = WriteReportFiles(incomplete, out_dir); !written) return written.error();
  if (auto removed = RemoveOldFiles(out_dir); !removed) return removed.error();
  return RunOutputFolder(std::move(lock).value(), out_dir, std::move(incomplete));
}

void RunOutputFolder::Reached(double simulated_s, std::ostream& notes) {
  incomplete_.set_simulated_s(simulated_s);
  auto written = WriteReportFiles(incomplete_, out_dir_);
  if (!written && !reached_noted_) {
    notes << "hilrig: cannot record the run's progress: " << written.error().message << "\n";
    reached_noted_ = true;
  }
}

rig::Result<void> RunOutputFolder::Finish(const proto::Report& report) const {
  return WriteReportFiles(report, out_dir_);
}

}  // namespace hilrig::host
