#include "host/report/stop_reason.h"

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hilrig::host {
namespace {

struct StopCase {
  RunStop stop;
  proto::StopReason kind;
  std::string text;  // the words report.json and the summary print, as they always were
};

std::vector<StopCase> EveryStop() {
  return {
      {{StopReason::kCompleted, ""}, proto::STOP_COMPLETED, "completed"},
      {{StopReason::kAborted, "low"}, proto::STOP_ABORTED, "aborted by envelope low"},
      {{StopReason::kInterrupted, ""}, proto::STOP_INTERRUPTED, "interrupted"},
      {{StopReason::kDutFailedToStart, "no dut_emu executable at /x"},
       proto::STOP_DUT_FAILED_TO_START,
       "dut failed to start: no dut_emu executable at /x"},
      {{StopReason::kDutFailed, "link closed by the DUT"},
       proto::STOP_DUT_FAILED,
       "dut failed: link closed by the DUT"},
      {{StopReason::kNumericalInstability, "the plant state is not finite after 1.5 s"},
       proto::STOP_NUMERICAL_INSTABILITY,
       "numerical instability: the plant state is not finite after 1.5 s"},
      {{StopReason::kIncomplete, ""}, proto::STOP_INCOMPLETE, "incomplete"},
      {{StopReason::kDutFault, "non-finite command servo_angle_rad = nan at 2 s"},
       proto::STOP_DUT_FAULT,
       "dut fault: non-finite command servo_angle_rad = nan at 2 s"},
  };
}

TEST(StopReasonTest, EveryReasonPrintsTheWordsItAlwaysPrinted) {
  for (const StopCase& stop : EveryStop()) {
    EXPECT_EQ(StopReasonText(stop.stop), stop.text);
  }
}

TEST(StopReasonTest, TheReportCarriesTheKindTheDetailAndTheirText) {
  for (const StopCase& stop : EveryStop()) {
    proto::Report report;
    SetStop(stop.stop, report);
    EXPECT_EQ(report.stop_kind(), stop.kind) << stop.text;
    EXPECT_EQ(report.stop_detail(), stop.stop.detail);
    EXPECT_EQ(report.stop_reason(), stop.text);
    EXPECT_EQ(RunCompleted(report), stop.stop.reason == StopReason::kCompleted) << stop.text;
  }
}

TEST(StopReasonTest, ReportJsonNamesTheKindBesideTheText) {
  proto::Report report;
  SetStop({StopReason::kAborted, "low"}, report);
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  std::string json;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(report, &json, options).ok());

  EXPECT_NE(json.find("\"stop_reason\":\"aborted by envelope low\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"stop_kind\":\"STOP_ABORTED\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"stop_detail\":\"low\""), std::string::npos) << json;
}

// A report whose text says "completed" but carries no kind (one made by hand) is no completed
// run: programs decide on the kind, never on the words.
TEST(StopReasonTest, TheTextAloneDoesNotMakeARunCompleted) {
  proto::Report report;
  report.set_stop_reason("completed");
  EXPECT_FALSE(RunCompleted(report));
}

TEST(StopReasonTest, ADutErrorFailsTheRunWithItsMessage) {
  const RunStop stop =
      StopForDutError(rig::MakeError(rig::ErrorCode::kTimeout, "dut did not answer tick 3"),
                      StopReason::kDutFailed);
  EXPECT_EQ(stop.reason, StopReason::kDutFailed);
  EXPECT_EQ(StopReasonText(stop), "dut failed: dut did not answer tick 3");

  const RunStop at_start =
      StopForDutError(rig::MakeError("no dut_emu executable"), StopReason::kDutFailedToStart);
  EXPECT_EQ(at_start.reason, StopReason::kDutFailedToStart);
  EXPECT_EQ(StopReasonText(at_start), "dut failed to start: no dut_emu executable");
}

TEST(StopReasonTest, ADutErrorAStopRequestCausedInterruptsTheRun) {
  const RunStop stop = StopForDutError(
      rig::MakeError(rig::ErrorCode::kInterrupted, "stopped while waiting for the dut"),
      StopReason::kDutFailedToStart);
  EXPECT_EQ(stop.reason, StopReason::kInterrupted);
  EXPECT_EQ(StopReasonText(stop), "interrupted");
}

}  // namespace
}  // namespace hilrig::host
