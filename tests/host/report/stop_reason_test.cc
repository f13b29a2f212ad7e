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

StopCase Case(StopReason reason, const char* detail, proto::StopReason kind, const char* text) {
  StopCase stop;
  stop.stop = RunStop{reason, detail};
  stop.kind = kind;
  stop.text = text;
  return stop;
}

// Built case by case: GCC 12 reports a false "may be used uninitialized" on the strings of a
// braced list of this struct.
std::vector<StopCase> EveryStop() {
  std::vector<StopCase> stops;
  stops.push_back(Case(StopReason::kCompleted, "", proto::STOP_COMPLETED, "completed"));
  stops.push_back(
      Case(StopReason::kAborted, "low", proto::STOP_ABORTED, "aborted by envelope low"));
  stops.push_back(Case(StopReason::kInterrupted, "", proto::STOP_INTERRUPTED, "interrupted"));
  stops.push_back(Case(StopReason::kDutFailedToStart, "no dut_emu executable at /x",
                       proto::STOP_DUT_FAILED_TO_START,
                       "dut failed to start: no dut_emu executable at /x"));
  stops.push_back(Case(StopReason::kDutFailed, "link closed by the DUT", proto::STOP_DUT_FAILED,
                       "dut failed: link closed by the DUT"));
  stops.push_back(Case(StopReason::kNumericalInstability,
                       "the plant state is not finite after 1.5 s",
                       proto::STOP_NUMERICAL_INSTABILITY,
                       "numerical instability: the plant state is not finite after 1.5 s"));
  stops.push_back(Case(StopReason::kIncomplete, "", proto::STOP_INCOMPLETE, "incomplete"));
  stops.push_back(Case(StopReason::kDutFault, "non-finite command servo_angle_rad = nan at 2 s",
                       proto::STOP_DUT_FAULT,
                       "dut fault: non-finite command servo_angle_rad = nan at 2 s"));
  return stops;
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
