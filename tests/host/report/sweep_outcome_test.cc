// A sweep case's outcome as runs.csv writes it, and read back: every outcome round-trips, and a
// word that is none of them reads as nothing.
#include "host/report/sweep_outcome.h"

#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

TEST(SweepOutcomeTest, EveryOutcomeReadsBackFromItsWord) {
  for (const auto outcome : {proto::SweepCaseResult::PASSED, proto::SweepCaseResult::FAILED,
                             proto::SweepCaseResult::STOPPED, proto::SweepCaseResult::INVALID,
                             proto::SweepCaseResult::SET_UP_FAILED}) {
    EXPECT_EQ(OutcomeNamed(OutcomeName(outcome)), outcome) << OutcomeName(outcome);
  }
  EXPECT_STREQ(OutcomeName(proto::SweepCaseResult::SET_UP_FAILED), "set_up_failed");
}

TEST(SweepOutcomeTest, AnUnknownOutcomeOrWordIsNamedAsSuchAndReadsAsNothing) {
  EXPECT_STREQ(OutcomeName(proto::SweepCaseResult::OUTCOME_UNSPECIFIED), "unknown");
  EXPECT_STREQ(OutcomeName(static_cast<proto::SweepCaseResult::Outcome>(99)), "unknown");
  EXPECT_EQ(OutcomeNamed("unknown"), std::nullopt);
  EXPECT_EQ(OutcomeNamed("Passed"), std::nullopt);
  EXPECT_EQ(OutcomeNamed(""), std::nullopt);
}

}  // namespace
}  // namespace hilrig::host
