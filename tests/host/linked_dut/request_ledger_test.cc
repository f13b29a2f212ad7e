// The ledger every DUT behind a link keeps its requests in: order, skipped and stale answers,
// answers to ticks never asked for, the bound, and the watchdog, on times the test chooses.
#include "host/linked_dut/request_ledger.h"

#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

constexpr std::int64_t kTimeoutNs = 1'000'000'000;

TEST(RequestLedgerTest, TicksOnlyGoForward) {
  RequestLedger ledger(kTimeoutNs);
  ASSERT_TRUE(ledger.CheckNext(3).ok());
  ledger.Add(3, 0);
  EXPECT_EQ(ledger.CheckNext(3).error().message, "tick 3 requested after tick 3");
  EXPECT_EQ(ledger.CheckNext(2).error().message, "tick 2 requested after tick 3");
  EXPECT_TRUE(ledger.CheckNext(4).ok());
}

TEST(RequestLedgerTest, AnAnswerTakesItsRequestAndSkipsTheOlderOnes) {
  RequestLedger ledger(kTimeoutNs);
  for (std::uint64_t tick = 1; tick <= 4; ++tick) ledger.Add(tick, std::int64_t(tick) * 100);
  const RequestLedger::Answer answer = ledger.Take(3, 1000);
  EXPECT_EQ(answer.outcome, RequestLedger::Outcome::kAnswers);
  EXPECT_EQ(answer.waited_ns, 700);
  EXPECT_EQ(ledger.requests_skipped(), 2u);
  EXPECT_EQ(ledger.last_answered(), 3u);
  // Tick 2 was skipped, and tick 3 answered: both are stale now.
  EXPECT_EQ(ledger.Take(2, 1100).outcome, RequestLedger::Outcome::kStale);
  EXPECT_EQ(ledger.Take(3, 1100).outcome, RequestLedger::Outcome::kStale);
  EXPECT_EQ(ledger.stale_answers(), 2u);
  EXPECT_EQ(ledger.Take(9, 1200).outcome, RequestLedger::Outcome::kNeverRequested);
  EXPECT_EQ(ledger.unrequested_answers(), 1u);
}

TEST(RequestLedgerTest, TheWatchdogNamesTheOldestRequestOnceItWaitedTooLong) {
  RequestLedger ledger(kTimeoutNs);
  EXPECT_FALSE(ledger.Overdue(5 * kTimeoutNs));  // nothing waits
  ledger.Add(7, 10);
  ledger.Add(8, 20);
  EXPECT_FALSE(ledger.Overdue(10 + kTimeoutNs));  // exactly the timeout: not yet
  EXPECT_EQ(ledger.Overdue(11 + kTimeoutNs), 7u);
  EXPECT_EQ(ledger.watchdog_timeouts(), 1u);
  EXPECT_EQ(OverdueError(7, 1.0).message, "the dut did not answer for 1 s (tick 7)");
  EXPECT_EQ(OverdueError(7, 1.0).code, rig::ErrorCode::kTimeout);
}

TEST(RequestLedgerTest, ADutFarBehindIsRefusedMoreRequests) {
  RequestLedger ledger(kTimeoutNs);
  for (std::uint64_t tick = 1; tick <= RequestLedger::kMaxOutstanding; ++tick) ledger.Add(tick, 0);
  const auto refused = ledger.CheckNext(RequestLedger::kMaxOutstanding + 1);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, "the dut fell 16384 requests behind");
}

}  // namespace
}  // namespace hilrig::host
