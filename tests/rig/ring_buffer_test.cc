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
