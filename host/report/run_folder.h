// The output folder of one `hilrig run` scenario, which must never read as a pass for a run that
// did not finish. Claiming it locks it (rig/folder_lock.h: a second run into it is refused), then,
// before the run writes anything, replaces report.json, junit.xml and index.html with an
// "incomplete" report (passed false, one failing junit case) and removes the previous run's plots.
// The runner's periodic flush updates how far the run got; the final report replaces it. A run
// that is killed, runs out of disk or fails on the way leaves "incomplete" beside its partial
// trace, never the previous run's "completed".
#pragma once

#include <ostream>
#include <string>

#include "proto/report.pb.h"
#include "rig/folder_lock.h"
#include "rig/result.h"

namespace hilrig::host {

// Writes junit.xml, then report.json (CI reads the verdict from junit.xml, so it goes first), then
// index.html with the plots the report lists (run_page.h).
rig::Result<void> WriteReportFiles(const proto::Report& report, const std::string& out_dir);

class RunOutputFolder {
 public:
  // Locks `out_dir` (made if missing) and marks it incomplete for the scenario `scenario` run from
  // `spec_file`.
  static rig::Result<RunOutputFolder> Claim(const std::string& out_dir, const std::string& scenario,
                                            const std::string& spec_file);

  // The run has flushed its trace up to `simulated_s`: the incomplete report says so. A failure
  // is noted once on `notes` and does not stop the run (the final report still has to be written,
  // and says what failed).
  void Reached(double simulated_s, std::ostream& notes);

  // The final report replaces the incomplete one.
  rig::Result<void> Finish(const proto::Report& report) const;

 private:
  RunOutputFolder(rig::FolderLock lock, std::string out_dir, proto::Report incomplete)
      : lock_(std::move(lock)), out_dir_(std::move(out_dir)), incomplete_(std::move(incomplete)) {}

  rig::FolderLock lock_;
  std::string out_dir_;
  proto::Report incomplete_;
  bool reached_noted_ = false;
};

}  // namespace hilrig::host
