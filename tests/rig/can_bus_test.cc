#include "rig/can_bus.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace hilrig::rig {
namespace {

CanFrame Standard(std::uint32_t id) { return CanFrame::Classic(id, {}); }
CanFrame Extended(std::uint32_t id) { return CanFrame::ClassicExtended(id, {}); }

TEST(FilterAcceptsTest, EmptyListAcceptsEverything) {
  EXPECT_TRUE(FilterAccepts({}, Standard(0x123)));
  EXPECT_TRUE(FilterAccepts({}, Extended(0x1234567)));
}

TEST(FilterAcceptsTest, ExactFilterPassesOnlyItsId) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x123, .mask = 0x7FF}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x123)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x124)));
}

TEST(FilterAcceptsTest, MaskSelectsARange) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x100, .mask = 0x7F0}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x107)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x110)));
}

TEST(FilterAcceptsTest, ExtendedFlagMustMatch) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x123, .mask = 0x7FF}};

  EXPECT_FALSE(FilterAccepts(filters, Extended(0x123)));
}

TEST(FilterAcceptsTest, ExtendedFilterMatchesExtendedFrames) {
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x18FF0000, .mask = 0x1FFF0000, .extended = true}};

  EXPECT_TRUE(FilterAccepts(filters, Extended(0x18FF1234)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x123)));
}

TEST(FilterAcceptsTest, InvertedFilterPassesEverythingElse) {
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x123, .mask = 0x7FF, .inverted = true}};

  EXPECT_FALSE(FilterAccepts(filters, Standard(0x123)));
  EXPECT_TRUE(FilterAccepts(filters, Standard(0x124)));
}

TEST(FilterAcceptsTest, AnyMatchingFilterPasses) {
  const std::array<CanFilter, 2> filters = {CanFilter{.id = 0x101, .mask = 0x7FF},
                                            CanFilter{.id = 0x202, .mask = 0x7FF}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x202)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x303)));
}

}  // namespace
}  // namespace hilrig::rig
