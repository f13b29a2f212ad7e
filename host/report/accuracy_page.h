// The pages of the force-accuracy commands, each written next to its JSON so that the figures
// read at a glance: accuracy.html beside accuracy.json (`hilrig accuracy`, proto AccuracyReport)
// and budget.html beside budget.json (`hilrig accuracy --budget`, proto AccuracyBudget). Each
// shows its message's figures as tables and a bar chart of the per-axis errors against the 0.02 N
// held-out target (host/report/bar_plot.h), in one self-contained document
// (host/report/html_page.h) that depends on the message alone: no clock, no absolute path.
#pragma once

#include <string>

#include "proto/calibration.pb.h"

namespace hilrig::host {

// The held-out target the pages draw and grade against: the compensated maximum error per axis.
inline constexpr double kHeldOutTargetN = 0.02;

// The condition the held-out sweep names its compensated figures by (the procedure,
// fixtures/calibration/calibration_procedure.cc, names it with this): the page grades that one.
inline constexpr const char* kCompensatedCondition = "compensated";

// The budget's configuration with every effect off (fixtures/calibration/accuracy_budget.cc names
// it with this): the decoding model's floor, whose z maximum the budget's chart marks.
inline constexpr const char* kFloorConfiguration = "none";

// The files the commands write into their output folder; each page links its JSON.
inline constexpr const char* kAccuracyJsonFile = "accuracy.json";
inline constexpr const char* kAccuracyPageFile = "accuracy.html";
inline constexpr const char* kBudgetJsonFile = "budget.json";
inline constexpr const char* kBudgetPageFile = "budget.html";

// The page of `hilrig accuracy`: a badge "within 0.02 N" (pass) when the compensated condition's
// maximum error is at most kHeldOutTargetN on every axis, "above 0.02 N" (fail) when not (or not
// finite), "no compensated condition" (neutral) without one; the conditions' table (per-axis
// RMSE, p95 and max, samples, flagged), the set-up, and a chart of the per-axis max and RMSE of
// each condition with the target as a line. Cannot fail: an empty report gives a page that says
// so.
std::string AccuracyPageHtml(const proto::AccuracyReport& report);

// The page of `hilrig accuracy --budget`: every row's configuration, effects on and per-axis RMSE
// and max; the floor, the floor with the effects alone (RSS), the measured total and the gap; the
// decoder alone on the exact field; and a chart of each row's per-axis max in file order, with
// lines at the floor's ("none" row's) z max and at the target. Cannot fail.
std::string BudgetPageHtml(const proto::AccuracyBudget& budget);

}  // namespace hilrig::host
