#include "host/report/stop_reason.h"

#include <cstddef>
#include <iterator>

#include "rig/check.h"

namespace hilrig::host {
namespace {

struct StopRow {
  StopReason reason;
  proto::StopReason kind;
  const char* text;  // the whole text, or the prefix of the detail
  bool has_detail;
};

constexpr StopRow kStopRows[] = {
    {StopReason::kCompleted, proto::STOP_COMPLETED, "completed", false},
    {StopReason::kAborted, proto::STOP_ABORTED, "aborted by envelope ", true},
    {StopReason::kInterrupted, proto::STOP_INTERRUPTED, "interrupted", false},
    {StopReason::kDutFailedToStart, proto::STOP_DUT_FAILED_TO_START, "dut failed to start: ", true},
    {StopReason::kDutFailed, proto::STOP_DUT_FAILED, "dut failed: ", true},
    {StopReason::kNumericalInstability, proto::STOP_NUMERICAL_INSTABILITY,
     "numerical instability: ", true},
    {StopReason::kIncomplete, proto::STOP_INCOMPLETE, "incomplete", false},
    {StopReason::kDutFault, proto::STOP_DUT_FAULT, "dut fault: ", true},
};

// The rows are in the enum's order.
const StopRow& RowOf(StopReason reason) {
  const auto index = static_cast<std::size_t>(reason);
  HILRIG_CHECK(index < std::size(kStopRows) && kStopRows[index].reason == reason,
               "a stop reason without its row in kStopRows");
  return kStopRows[index];
}

}  // namespace

std::string StopReasonText(const RunStop& stop) {
  const StopRow& row = RowOf(stop.reason);
  return row.has_detail ? row.text + stop.detail : std::string(row.text);
}

RunStop StopForDutError(const rig::Error& error, StopReason failure) {
  if (error.code == rig::ErrorCode::kInterrupted) return {StopReason::kInterrupted, {}};
  return {failure, error.message};
}

rig::Error StoppedShortError(std::string message, const proto::Report& report) {
  const bool interrupted = report.stop_kind() == proto::STOP_INTERRUPTED;
  return rig::MakeError(interrupted ? rig::ErrorCode::kInterrupted : rig::ErrorCode::kUnspecified,
                        std::move(message) + report.stop_reason());
}

void SetStop(const RunStop& stop, proto::Report& report) {
  report.set_stop_kind(RowOf(stop.reason).kind);
  report.set_stop_detail(stop.detail);
  report.set_stop_reason(StopReasonText(stop));
}

bool RunCompleted(const proto::Report& report) {
  return report.stop_kind() == proto::STOP_COMPLETED;
}

}  // namespace hilrig::host
