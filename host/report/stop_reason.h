// Why a run ended, as a value that the runner sets and the report files, the CLI and the bench
// decide on. The words a person reads (report.json's stop_reason, the summary's stop column:
// "completed", "aborted by envelope low", "dut failed: ...") are made from it in one place,
// StopReasonText, so they cannot drift from what the code tests.
#pragma once

#include <string>

#include "proto/report.pb.h"
#include "rig/result.h"

namespace hilrig::host {

enum class StopReason {
  kCompleted,
  kAborted,  // an envelope with abort_on_violation failed; the detail names it
  kInterrupted,
  kDutFailedToStart,
  kDutFailed,
  kNumericalInstability,
  kIncomplete,  // the run is still going, or was killed or failed on the way
  kDutFault,    // the DUT commanded what the plant cannot take; the detail says what
};

struct RunStop {
  StopReason reason = StopReason::kCompleted;
  std::string detail;  // the envelope, the DUT's error, what was not finite; empty otherwise
};

// "completed", "aborted by envelope <detail>", "interrupted", "dut failed to start: <detail>",
// "dut failed: <detail>", "numerical instability: <detail>", "incomplete", "dut fault: <detail>".
std::string StopReasonText(const RunStop& stop);

// A DUT's error ends the run as `failure` (kDutFailedToStart or kDutFailed) with its message,
// unless a stop request caused it: then the run was interrupted.
RunStop StopForDutError(const rig::Error& error, StopReason failure);

// The error for a run that had to complete and did not: `message` then the run's stop reason, of
// code kInterrupted when a stop request ended the run.
rig::Error StoppedShortError(std::string message, const proto::Report& report);

// Sets the report's stop_kind, stop_detail and their text, stop_reason.
void SetStop(const RunStop& stop, proto::Report& report);
bool RunCompleted(const proto::Report& report);

}  // namespace hilrig::host
