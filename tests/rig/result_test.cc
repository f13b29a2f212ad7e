#include "rig/result.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace hilrig::rig {
namespace {

TEST(ResultTest, HoldsValue) {
  const Result<int> result(42);

  EXPECT_TRUE(result.ok());
  EXPECT_TRUE(static_cast<bool>(result));
  EXPECT_EQ(result.value(), 42);
}

TEST(ResultTest, HoldsError) {
  const Result<int> result(MakeError("no sensor"));

  EXPECT_FALSE(result.ok());
  EXPECT_EQ(result.error().message, "no sensor");
}

TEST(ResultTest, MovesValueOut) {
  Result<std::unique_ptr<int>> result(std::make_unique<int>(7));

  const std::unique_ptr<int> owned = std::move(result).value();

  ASSERT_NE(owned, nullptr);
  EXPECT_EQ(*owned, 7);
}

TEST(ResultTest, VoidDefaultIsOk) {
  const Result<void> result;

  EXPECT_TRUE(result.ok());
}

TEST(ResultTest, VoidHoldsError) {
  const Result<void> result(MakeError("bus off"));

  EXPECT_FALSE(result);
  EXPECT_EQ(result.error().message, "bus off");
}

TEST(ResultTest, AnErrorWithoutACodeIsUnspecified) {
  const Error error = MakeError("no sensor");

  EXPECT_EQ(error.code, ErrorCode::kUnspecified);
  EXPECT_EQ(error.subcode, 0);
}

TEST(ResultTest, AnErrorKeepsItsCodeBesideItsMessage) {
  const Result<int> result(MakeError(ErrorCode::kInterrupted, "interrupted"));

  EXPECT_EQ(result.error().code, ErrorCode::kInterrupted);
  EXPECT_EQ(result.error().message, "interrupted");
}

// Context added on the way up (a path, a step) must not lose what a caller decides on.
TEST(ResultTest, ContextGoesBeforeTheMessageAndKeepsTheCodes) {
  Error inner = MakeError(ErrorCode::kLinkProtocol, "malformed: bad bytes");
  inner.subcode = 3;

  const Error outer = InContext("scenes/hover.textproto: ", inner);

  EXPECT_EQ(outer.message, "scenes/hover.textproto: malformed: bad bytes");
  EXPECT_EQ(outer.code, ErrorCode::kLinkProtocol);
  EXPECT_EQ(outer.subcode, 3);
}

TEST(ResultDeathTest, ValueOfErrorAbortsWithItsMessage) {
  const Result<int> result(MakeError("decoder gave up"));

  EXPECT_DEATH((void)result.value(), "decoder gave up");
}

TEST(CheckDeathTest, FailingCheckNamesFileAndLine) {
  EXPECT_DEATH(HILRIG_CHECK(1 + 1 == 3, "arithmetic broke"),
               "result_test.cc:[0-9]+.*arithmetic broke");
}

}  // namespace
}  // namespace hilrig::rig
