// The two ways a run gets the DUT's command, against a DUT whose answers the test chooses:
// lockstep takes the answer at once and never has one waiting; real time asks without waiting,
// applies the newest command that arrived at the next control tick, counts a tick without one as
// missed on the pacer, and keeps the first failure.
#include "host/runner/command_exchange.h"

#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "rig/clock.h"

namespace hilrig::host {
namespace {

// Answers Step at once; in real time, hands out what the test queued, one poll at a time.
class QueuedDut final : public DutPort {
 public:
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t) override {
    ActuatorMessage command;
    command.answers_sequence = tick;
    return command;
  }
  void RequestStep(std::uint64_t tick, std::int64_t) override { requested.push_back(tick); }
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override {
    if (fail) return rig::MakeError("the dut died");
    if (queued.empty()) return std::optional<ActuatorMessage>();
    ActuatorMessage command = queued.front();
    queued.pop_front();
    return std::optional<ActuatorMessage>(command);
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "queued"; }

  std::vector<std::uint64_t> requested;
  std::deque<ActuatorMessage> queued;
  bool fail = false;
};

ActuatorMessage Answering(std::uint64_t tick) {
  ActuatorMessage command;
  command.answers_sequence = tick;
  return command;
}

TEST(CommandExchangeTest, LockstepTakesTheAnswerAtOnce) {
  QueuedDut dut;
  const std::unique_ptr<CommandExchange> exchange = MakeCommandExchange(nullptr);
  ActuatorMessage command;
  EXPECT_FALSE(exchange->Arrived(dut, command).value());
  ASSERT_TRUE(exchange->Ask(dut, 7, 7'000'000, command).value());
  EXPECT_EQ(command.answers_sequence, 7u);
  EXPECT_TRUE(dut.requested.empty());
}

TEST(CommandExchangeTest, RealTimeAppliesTheNewestArrivalAndCountsMisses) {
  QueuedDut dut;
  rig::FakePacingClock clock;
  RealtimePacer pacer(clock, PacerSettings{});
  const std::unique_ptr<CommandExchange> exchange = MakeCommandExchange(&pacer);
  ActuatorMessage command;
  ASSERT_FALSE(exchange->Arrived(dut, command).value());  // the first tick: nothing yet
  EXPECT_FALSE(exchange->Ask(dut, 0, 0, command).value());
  EXPECT_EQ(dut.requested, std::vector<std::uint64_t>{0});
  dut.queued = {Answering(0), Answering(1)};
  exchange->Collect(dut);  // between ticks
  ASSERT_TRUE(exchange->Arrived(dut, command).value());
  EXPECT_EQ(command.answers_sequence, 1u);  // the newer of the two
  EXPECT_FALSE(exchange->Arrived(dut, command).value());
  EXPECT_EQ(pacer.dut_commands_missed(), 1u);
}

TEST(CommandExchangeTest, RealTimeKeepsTheFirstFailure) {
  QueuedDut dut;
  rig::FakePacingClock clock;
  RealtimePacer pacer(clock, PacerSettings{});
  const std::unique_ptr<CommandExchange> exchange = MakeCommandExchange(&pacer);
  dut.fail = true;
  exchange->Collect(dut);
  dut.fail = false;
  ActuatorMessage command;
  const auto arrived = exchange->Arrived(dut, command);
  ASSERT_FALSE(arrived.ok());
  EXPECT_EQ(arrived.error().message, "the dut died");
}

}  // namespace
}  // namespace hilrig::host
