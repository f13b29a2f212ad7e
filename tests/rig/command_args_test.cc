#include "rig/command_args.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::rig {
namespace {

using ::testing::HasSubstr;

TEST(DidYouMeanTest, NamesTheNearestCandidateWithinTwoEdits) {
  const std::set<std::string> options = {"--out", "--seed", "--set", "--scenes"};

  EXPECT_EQ(DidYouMean("--sed", options), " (did you mean --seed?)");  // one edit from both
  EXPECT_EQ(DidYouMean("--scene", options), " (did you mean --scenes?)");
  EXPECT_EQ(DidYouMean("--ou", options), " (did you mean --out?)");
  EXPECT_EQ(DidYouMean("--frobnicate", options), "");
  EXPECT_EQ(DidYouMean("--seed", {}), "");
}

TEST(ParseCliArgsTest, AnUnknownOptionSuggestsTheNearestKnownOne) {
  const auto parsed = ParseCliArgs({"run", "spec.textproto", "--sed", "3"}, {"--seed", "--out"});

  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().message, "unknown option --sed (did you mean --seed?)");
  const auto far = ParseCliArgs({"run", "--frobnicate", "1"}, {"--seed", "--out"});
  ASSERT_FALSE(far.ok());
  EXPECT_EQ(far.error().message, "unknown option --frobnicate");
}

// A flag the command took out of the arguments before is still a name a typo may be near.
TEST(ParseCliArgsTest, AnUnknownOptionMaySuggestAFlag) {
  const auto parsed =
      ParseCliArgs({"run", "spec.textproto", "--no-mcpa"}, {"--seed"}, {"--no-mcap", "--realtime"});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().message, "unknown option --no-mcpa (did you mean --no-mcap?)");
}

TEST(ParseCliArgsTest, KeepsPositionalsAndOptions) {
  const auto parsed = ParseCliArgs({"run", "a", "--out", "DIR", "b"}, {"--out"});

  ASSERT_TRUE(parsed.ok());
  EXPECT_THAT(parsed.value().positional, ::testing::ElementsAre("a", "b"));
  ASSERT_NE(parsed.value().Option("--out"), nullptr);
  EXPECT_EQ(*parsed.value().Option("--out"), "DIR");
  const auto missing = ParseCliArgs({"run", "--out"}, {"--out"});
  ASSERT_FALSE(missing.ok());
  EXPECT_THAT(missing.error().message, HasSubstr("--out needs a value"));
}

}  // namespace
}  // namespace hilrig::rig
