// The session every linked DUT runs, over a scripted link and a simulated clock: what it asks of
// the link, how it matches answers to requests, when it retries, and every failure it names.

#include "host/linked_dut/linked_dut.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "host/link/hil_link_codec.h"
#include "host/linked_dut/fake_dut_link.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"

namespace hilrig::host {
namespace {

constexpr std::int64_t kTickNs = 1'000'000;

struct Session {
  explicit Session(DutPacing pacing = DutPacing::kLockstep,
                   std::optional<std::int64_t> resend_after = std::nullopt) {
    auto owned = std::make_unique<FakeDutLink>(&clock);
    link = owned.get();
    link->resend_after = resend_after;
    LinkedDutOptions options;
    options.pacing = pacing;
    options.answer_timeout_s = 0.5;
    options.clock = &clock;
    dut = std::make_unique<LinkedDut>(std::move(owned), bus.Connect("dut"), options);
  }

  double Metric(const std::string& name) const {
    for (const rig::Metric& metric : dut->link_metrics()) {
      if (metric.name == name) return metric.value;
    }
    return -1;
  }

  rig::SimClock clock;
  rig::EmulatedBus bus;
  std::unique_ptr<rig::CanBus> sensor = bus.Connect("hall");
  FakeDutLink* link = nullptr;
  std::unique_ptr<LinkedDut> dut;
};

TEST(LinkedDutTest, AStepSendsTheTicksFramesAndReturnsItsAnswer) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  rig::CanFrame frame;
  frame.id = 0x101;
  frame.length = 1;
  ASSERT_TRUE(s.sensor->Send(frame, 500'000));
  s.link->Answer(1);
  auto command = s.dut->Step(1, kTickNs);
  ASSERT_TRUE(command) << command.error().message;
  EXPECT_EQ(command.value().answers_sequence, 1u);
  ASSERT_EQ(s.link->requests.size(), 1u);
  EXPECT_EQ(s.link->requests[0].frames, 1u);
  EXPECT_FALSE(s.link->requests[0].realtime);
  EXPECT_EQ(s.dut->counters().can_frames_received, 1u);
  EXPECT_EQ(s.Metric("fake_commands_received"), 1);
  EXPECT_EQ(s.Metric("fake_requests"), 1);  // the link's own
}

// The front end's counts are the DUT's: none from a link that does not carry them, the DUT's own
// from one that does.
TEST(LinkedDutTest, FrontEndCountsComeFromTheDutOrAreNotCounted) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  EXPECT_FALSE(s.dut->counters().front_end_counted);
  proto::DutFrontEndCounters reported;
  reported.set_can_frames_rejected(1);
  reported.set_sensor_samples(40);
  reported.set_sensor_sequence_gaps(2);
  reported.set_sensor_samples_lost(3);
  reported.set_tactile_samples_flagged(4);
  s.link->front_end = reported;
  const DutCounters counters = s.dut->counters();
  EXPECT_TRUE(counters.front_end_counted);
  EXPECT_EQ(counters.can_frames_rejected, 1u);
  EXPECT_EQ(counters.sensor_samples, 40u);
  EXPECT_EQ(counters.sensor_sequence_gaps, 2u);
  EXPECT_EQ(counters.sensor_samples_lost, 3u);
  EXPECT_EQ(counters.tactile_samples_flagged, 4u);
}

TEST(LinkedDutTest, ALossyLinkRepeatsTheRequestAndSkipsTheTwinAnswer) {
  Session s(DutPacing::kLockstep, /*resend_after=*/50'000'000);
  ASSERT_TRUE(s.dut->Start());
  s.link->Answer(1);
  ASSERT_TRUE(s.dut->Step(1, kTickNs));
  // Tick 2's request is lost: nothing for three 20 ms slices, then the repeat at 50 ms is
  // answered, after a late twin of tick 1's answer.
  for (int slice = 0; slice < 3; ++slice) s.link->events.push_back({});
  s.link->Answer(1);
  s.link->Answer(2);
  auto command = s.dut->Step(2, 2 * kTickNs);
  ASSERT_TRUE(command) << command.error().message;
  EXPECT_EQ(command.value().answers_sequence, 2u);
  EXPECT_EQ(s.link->resends, 1u);
  EXPECT_EQ(s.Metric("fake_stale_answers"), 1);
}

TEST(LinkedDutTest, ALinkThatNeverRepeatsFailsAnAnswerThatGoesBackwards) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  s.link->Answer(1);
  ASSERT_TRUE(s.dut->Step(1, kTickNs));
  s.link->Answer(1);
  const auto command = s.dut->Step(2, 2 * kTickNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message,
            "the dut answered tick 1 after tick 1 (answers went backwards)");
  EXPECT_EQ(LinkErrorKindOf(command.error()), LinkErrorKind::kOutOfOrder);
}

TEST(LinkedDutTest, AnAnswerToALaterTickIsNeverRequested) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  s.link->Answer(2);
  const auto command = s.dut->Step(1, kTickNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message,
            "the dut answered tick 2, which was never requested (last request: tick 1)");
  EXPECT_EQ(s.Metric("fake_requests_skipped"), 0);  // tick 1 was not skipped, it failed
}

TEST(LinkedDutTest, ASilentDutTripsTheWatchdogOnTheInjectedClock) {
  Session s(DutPacing::kLockstep, /*resend_after=*/100'000'000);
  ASSERT_TRUE(s.dut->Start());
  const auto command = s.dut->Step(1, kTickNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().code, rig::ErrorCode::kTimeout);
  EXPECT_EQ(command.error().message, "the dut did not answer tick 1 within 0.5 s");
  EXPECT_EQ(s.clock.NowNs(), 500'000'000);
  EXPECT_EQ(s.link->resends, 4u);  // at 0.1, 0.2, 0.3 and 0.4 s
  EXPECT_EQ(s.Metric("fake_watchdog_timeouts"), 1);
}

TEST(LinkedDutTest, AClosedLinkIsNamedByTheExitOfTheProcessBehindIt) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  s.link->peer = true;
  s.link->peer_exit = "dut process exited with status 3";
  s.link->events.push_back(
      {DutLinkEventKind::kClosed, 0, rig::MakeError(rig::ErrorCode::kLinkClosed, "closed")});
  const auto command = s.dut->Step(1, kTickNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message, "dut process exited with status 3");
  const auto again = s.dut->Step(2, 2 * kTickNs);  // the failure sticks
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error().message, command.error().message);
  s.dut->Stop();
  EXPECT_EQ(s.link->closed_with_goodbye, false);  // no goodbye after a failure
}

TEST(LinkedDutTest, ABrokenMessageFailsTheRunWithTheLinksWords) {
  Session s;
  ASSERT_TRUE(s.dut->Start());
  s.link->events.push_back({DutLinkEventKind::kFailed, 0, rig::MakeError("dut ended the link")});
  const auto command = s.dut->Step(1, kTickNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message, "dut ended the link");
}

TEST(LinkedDutTest, PacingIsChosenOnceAndRefusedTheOtherWay) {
  Session lockstep;
  ASSERT_TRUE(lockstep.dut->Start());
  lockstep.dut->RequestStep(1, kTickNs);
  const auto polled = lockstep.dut->PollCommand();
  ASSERT_FALSE(polled);
  EXPECT_NE(polled.error().message.find("lockstep dut"), std::string::npos);

  LinkedDutOptions no_clock;
  no_clock.pacing = DutPacing::kRealtime;
  const auto refused = ValidateLinkedDutOptions(no_clock);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("needs a wall clock"), std::string::npos);
}

TEST(LinkedDutTest, APollKeepsTheNewestAnswerAndCountsTheOthers) {
  Session s(DutPacing::kRealtime);
  ASSERT_TRUE(s.dut->Start());
  s.dut->RequestStep(1, kTickNs);
  s.dut->RequestStep(2, 2 * kTickNs);
  s.link->Answer(1);
  s.link->Answer(2);
  auto polled = s.dut->PollCommand();
  ASSERT_TRUE(polled) << polled.error().message;
  ASSERT_TRUE(polled.value());
  EXPECT_EQ(polled.value()->answers_sequence, 2u);
  EXPECT_TRUE(s.link->requests[0].realtime);
  EXPECT_EQ(s.Metric("fake_commands_superseded"), 1);
  const std::vector<StreamLatency> latencies = s.dut->response_latencies();
  ASSERT_EQ(latencies.size(), 1u);
  EXPECT_EQ(latencies[0].stream, "command");
}

TEST(LinkedDutTest, TheRealTimeWatchdogNamesTheOldestUnansweredTick) {
  Session s(DutPacing::kRealtime);
  ASSERT_TRUE(s.dut->Start());
  s.dut->RequestStep(1, kTickNs);
  s.dut->RequestStep(2, 2 * kTickNs);
  ASSERT_TRUE(s.dut->PollCommand());
  s.clock.AdvanceNs(500'000'001);
  const auto polled = s.dut->PollCommand();
  ASSERT_FALSE(polled);
  EXPECT_EQ(polled.error().message, "the dut did not answer for 0.5 s (tick 1)");
}

TEST(LinkedDutTest, ARealTimeLinkThatClosedIsNamedAfterAGraceForTheExit) {
  Session s(DutPacing::kRealtime);
  ASSERT_TRUE(s.dut->Start());
  s.dut->RequestStep(1, kTickNs);
  s.link->events.push_back(
      {DutLinkEventKind::kClosed, 0,
       rig::MakeError(rig::ErrorCode::kLinkClosed, "the dut closed the link")});
  ASSERT_TRUE(s.dut->PollCommand());  // the exit may still follow
  s.clock.AdvanceNs(100'000'000);
  ASSERT_TRUE(s.dut->PollCommand());
  s.clock.AdvanceNs(100'000'000);
  const auto polled = s.dut->PollCommand();
  ASSERT_FALSE(polled);
  EXPECT_EQ(polled.error().message, "the dut closed the link");
}

TEST(LinkedDutTest, ARealTimeSendToAClosedLinkWaitsForTheExitThenNamesIt) {
  Session s(DutPacing::kRealtime);
  ASSERT_TRUE(s.dut->Start());
  s.link->send_result = rig::MakeError(rig::ErrorCode::kLinkClosed, "the dut closed the link");
  s.dut->RequestStep(1, kTickNs);
  ASSERT_TRUE(s.dut->PollCommand());
  s.link->peer_exit = "dut process killed by signal 9";
  const auto polled = s.dut->PollCommand();
  ASSERT_FALSE(polled);
  EXPECT_EQ(polled.error().message, "dut process killed by signal 9");
}

TEST(LinkedDutTest, StartsOnceAndSaysGoodbyeOnAGoodStop) {
  Session s;
  EXPECT_FALSE(s.dut->Step(1, kTickNs));  // not started
  Session t;
  ASSERT_TRUE(t.dut->Start());
  EXPECT_FALSE(t.dut->Start());
  t.dut->Stop();
  t.dut->Stop();
  EXPECT_EQ(t.link->closed_with_goodbye, true);
  EXPECT_FALSE(t.dut->Step(1, kTickNs));
}

TEST(LinkedDutTest, AFailedOpenSticksAndClosesWithoutAGoodbye) {
  Session s;
  s.link->open_result = rig::MakeError("the dut refused the firmware configuration: no");
  const auto started = s.dut->Start();
  ASSERT_FALSE(started);
  EXPECT_EQ(started.error().message, "the dut refused the firmware configuration: no");
  s.dut->Stop();
  EXPECT_EQ(s.link->closed_with_goodbye, false);
}

}  // namespace
}  // namespace hilrig::host
