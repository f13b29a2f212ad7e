#include "rig/ring_buffer.h"

#include <gtest/gtest.h>

#include <vector>

namespace hilrig::rig {
namespace {

std::vector<int> Drain(RingBuffer<int>& buffer) {
  std::vector<int> out;
  while (!buffer.empty()) {
    out.push_back(buffer.front());
    buffer.pop_front();
  }
  return out;
}

TEST(RingBufferTest, SlotsFilledInPlaceKeepFifoOrderAcrossGrowthWhileWrapped) {
  RingBuffer<int> buffer;
  for (int i = 0; i < 12; ++i) buffer.AppendSlot() = i;
  for (int i = 0; i < 10; ++i) buffer.pop_front();
  for (int i = 12; i < 50; ++i) buffer.AppendSlot() = i;  // wraps, then grows twice

  std::vector<int> expected;
  for (int i = 10; i < 50; ++i) expected.push_back(i);
  EXPECT_EQ(buffer.size(), expected.size());
  EXPECT_EQ(Drain(buffer), expected);
}

TEST(RingBufferTest, KeepsFifoOrderAcrossGrowthWhileWrapped) {
  RingBuffer<int> buffer;
  for (int i = 0; i < 10; ++i) buffer.push_back(i);
  for (int i = 0; i < 8; ++i) buffer.pop_front();  // head now mid-array

  for (int i = 10; i < 40; ++i) buffer.push_back(i);  // wraps, then grows

  std::vector<int> expected;
  for (int i = 8; i < 40; ++i) expected.push_back(i);
  EXPECT_EQ(Drain(buffer), expected);
}

TEST(RingBufferTest, PopFrontIntoTakesTheLeadingRunAcrossTheWrapAndStopsAtTheFirstRefusal) {
  RingBuffer<int> buffer;
  for (int i = 0; i < 16; ++i) buffer.push_back(i);
  for (int i = 0; i < 12; ++i) buffer.pop_front();
  for (int i = 16; i < 24; ++i) buffer.push_back(i);  // 12..23, wrapped at 16 without growing
  ASSERT_EQ(buffer.capacity(), 16u);

  std::vector<int> out = {-1};
  const auto below = [](int limit) { return [limit](int v) { return v < limit; }; };
  EXPECT_EQ(buffer.PopFrontInto(out, below(20)), 8u);  // 12..19: four before the wrap, four after
  EXPECT_EQ(out, (std::vector<int>{-1, 12, 13, 14, 15, 16, 17, 18, 19}));
  EXPECT_EQ(buffer.PopFrontInto(out, below(0)), 0u);  // 20 is refused: nothing moves
  buffer.push_back(5);                                // 20..23, 5: taking stops at 5's refusal
  out.clear();
  EXPECT_EQ(buffer.PopFrontInto(out, [](int v) { return v >= 20; }), 4u);
  EXPECT_EQ(out, (std::vector<int>{20, 21, 22, 23}));
  EXPECT_EQ(Drain(buffer), std::vector<int>{5});

  RingBuffer<int> never_grown;
  EXPECT_EQ(never_grown.PopFrontInto(out, below(100)), 0u);
}

TEST(RingBufferTest, SteadyTrafficDoesNotGrow) {
  RingBuffer<int> buffer;
  for (int i = 0; i < 10; ++i) buffer.push_back(i);
  const std::size_t capacity = buffer.capacity();

  for (int i = 0; i < 1000; ++i) {
    buffer.push_back(i);
    buffer.pop_front();
  }

  EXPECT_EQ(buffer.capacity(), capacity);
  EXPECT_EQ(buffer.size(), 10u);
}

TEST(RingBufferDeathTest, PopOnEmptyAborts) {
  RingBuffer<int> buffer;

  EXPECT_DEATH(buffer.pop_front(), "empty RingBuffer");
}

}  // namespace
}  // namespace hilrig::rig
