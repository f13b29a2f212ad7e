// A byte queue between one interrupt handler (the only writer) and the main loop (the only
// reader). Each side owns one index, so neither needs to mask interrupts; the atomics order the
// byte's store before the index that publishes it. A byte that finds the queue full is dropped
// and counted: the receiver must never block in an interrupt.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace hilrig::dut_fw::target {

template <std::size_t kCapacity>
class RingBuffer {
  static_assert(kCapacity > 0 && (kCapacity & (kCapacity - 1)) == 0,
                "capacity must be a power of two so the free-running indices wrap cleanly");

 public:
  // Interrupt side.
  void Push(std::uint8_t byte) {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == kCapacity) {
      dropped_.store(dropped_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
      return;
    }
    bytes_[head % kCapacity] = byte;
    head_.store(head + 1, std::memory_order_release);
  }

  // Main-loop side.
  std::optional<std::uint8_t> Pop() {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return std::nullopt;
    const std::uint8_t byte = bytes_[tail % kCapacity];
    tail_.store(tail + 1, std::memory_order_release);
    return byte;
  }

  std::uint32_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::array<std::uint8_t, kCapacity> bytes_{};
  std::atomic<std::uint32_t> head_{0};
  std::atomic<std::uint32_t> tail_{0};
  std::atomic<std::uint32_t> dropped_{0};
};

}  // namespace hilrig::dut_fw::target
