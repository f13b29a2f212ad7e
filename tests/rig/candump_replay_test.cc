#include "rig/candump_replay.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "rig/emulated_bus.h"

namespace hilrig::rig {
namespace {

constexpr const char* kLog =
    "(1000.000000) can0 101#01 R\n"
    "(1000.010000) can0 102#02 T\n"
    "(1000.030000) can0 103#03\n";

class CandumpReplayTest : public ::testing::Test {
 protected:
  CandumpReplayTest() : player_(bus_.Connect("player")), listener_(bus_.Connect("listener")) {}

  std::vector<std::uint32_t> IdsHeardBy(std::int64_t now_ns) {
    std::vector<TimedCanFrame> frames;
    listener_->Receive(now_ns, frames);
    std::vector<std::uint32_t> ids;
    for (const auto& frame : frames) ids.push_back(frame.frame.id);
    return ids;
  }

  EmulatedBus bus_;
  std::unique_ptr<CanBus> player_;
  std::unique_ptr<CanBus> listener_;
};

TEST_F(CandumpReplayTest, SendsEachFrameAtItsRecordedOffset) {
  std::istringstream log(kLog);
  auto replay = CandumpReplay::Read(log, 1.0);
  ASSERT_TRUE(replay.ok()) << replay.error().message;
  const std::int64_t start_ns = 5'000'000'000;
  EXPECT_EQ(replay.value().Tick(start_ns, *player_), 1u);
  EXPECT_EQ(replay.value().Tick(start_ns + 9'999'999, *player_), 0u);
  EXPECT_EQ(replay.value().Tick(start_ns + 10'000'000, *player_), 1u);
  EXPECT_EQ(replay.value().Tick(start_ns + 30'000'000, *player_), 1u);
  EXPECT_TRUE(replay.value().done());
  EXPECT_THAT(IdsHeardBy(start_ns + 31'000'000), ::testing::ElementsAre(0x101, 0x102, 0x103));
}

TEST_F(CandumpReplayTest, AcceleratedReplayCompressesTime) {
  std::istringstream log(kLog);
  auto replay = CandumpReplay::Read(log, 10.0);
  ASSERT_TRUE(replay.ok());
  replay.value().Tick(0, *player_);
  EXPECT_EQ(replay.value().Tick(3'000'000, *player_), 2u);  // 30 ms recorded in 3 ms
}

TEST_F(CandumpReplayTest, MalformedLineNamesItsNumber) {
  std::istringstream log("(1.000000) can0 101#01\n(1.000000) can0 10G#01\n");
  const auto replay = CandumpReplay::Read(log, 1.0);
  ASSERT_FALSE(replay.ok());
  EXPECT_THAT(replay.error().message, ::testing::HasSubstr("line 2"));
}

TEST_F(CandumpReplayTest, AMalformedLineIsNamedByNumberNotQuoted) {
  std::istringstream log("(1.000000) can0 101#01\nhunter2secret was here\n");
  const auto replay = CandumpReplay::Read(log, 1.0);
  ASSERT_FALSE(replay.ok());
  EXPECT_THAT(replay.error().message, ::testing::HasSubstr("line 2: bad candump line"));
  EXPECT_THAT(replay.error().message, ::testing::Not(::testing::HasSubstr("hunter2")));
}

TEST_F(CandumpReplayTest, ALineLongerThanAnyCandumpLineIsAnErrorNamingIt) {
  std::istringstream log("(1.000000) can0 101#01\n(1.000000) can0 101#" +
                         std::string(kMaxCandumpLineBytes, '0') + "\n");
  const auto replay = CandumpReplay::Read(log, 1.0);
  ASSERT_FALSE(replay.ok());
  EXPECT_THAT(replay.error().message, ::testing::HasSubstr("line 2: longer than 1024 bytes"));
}

TEST_F(CandumpReplayTest, RejectsNonPositiveSpeed) {
  std::istringstream log(kLog);
  EXPECT_FALSE(CandumpReplay::Read(log, 0.0).ok());
}

}  // namespace
}  // namespace hilrig::rig
