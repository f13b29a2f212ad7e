// RingBuffer is the FIFO behind emulated RX queues. Unlike std::deque it never frees or allocates
// once it has grown to the working-set size, which keeps per-frame bus traffic allocation-free.
// Capacity is a power of two so that wrapping is a mask, not a division.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "rig/check.h"

namespace hilrig::rig {

template <typename T>
class RingBuffer {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }

  const T& front() const {
    HILRIG_CHECK(!empty(), "front() on an empty RingBuffer");
    return slots_[head_];
  }

  void push_back(const T& value) { AppendSlot() = value; }

  // Appends a slot, holding whatever it held before, for the caller to fill in place: a value
  // built from parts (a frame and its time) is written once instead of built and copied.
  T& AppendSlot() {
    if (size_ == capacity_) Grow();
    return slots_[(head_ + size_++) & mask_];
  }

  void pop_front() {
    HILRIG_CHECK(!empty(), "pop_front() on an empty RingBuffer");
    head_ = (head_ + 1) & mask_;
    --size_;
  }

  // Moves the leading values for which `take` holds to the end of `out`, in order, and returns
  // how many. Never fails; O(taken) and at most two block copies into `out` (which allocates only
  // if it has to grow), where a value at a time would check and copy each one separately.
  template <typename Take>
  std::size_t PopFrontInto(std::vector<T>& out, Take take) {
    std::size_t taken = 0;
    while (taken < size_ && take(slots_[(head_ + taken) & mask_])) ++taken;
    const std::size_t first = std::min(taken, capacity_ - head_);  // up to the end of slots_
    out.insert(out.end(), slots_.begin() + head_, slots_.begin() + head_ + first);
    out.insert(out.end(), slots_.begin(), slots_.begin() + (taken - first));
    head_ = (head_ + taken) & mask_;
    size_ -= taken;
    return taken;
  }

 private:
  static constexpr std::size_t kInitialCapacity = 16;

  void Grow() {
    std::vector<T> bigger(std::max(kInitialCapacity, 2 * capacity_));
    for (std::size_t i = 0; i < size_; ++i) {
      bigger[i] = std::move(slots_[(head_ + i) & mask_]);
    }
    slots_.swap(bigger);
    capacity_ = slots_.size();
    mask_ = capacity_ - 1;
    head_ = 0;
  }

  std::vector<T> slots_;
  // slots_.size() and one less, kept so that no access divides by sizeof(T) to find the size.
  std::size_t capacity_ = 0;
  std::size_t mask_ = 0;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace hilrig::rig
