// The HIL link's shared-memory transport between a runner and a DUT process on the same host: one
// memfd mapping with two single-producer/single-consumer byte rings (runner to DUT, DUT to
// runner), each end a ByteStream, so the same length-delimited LinkMessage frames of
// host/link/hil_link_codec.h travel on it as on TCP. A lockstep tick costs a memcpy and an index
// store each way, no system call: a writer publishes with a release store and wakes the reader
// with a futex only when the reader said it sleeps; a reader spins (with a pause instruction)
// (yielding the core after a while) for kShmSpinNs before it sleeps on the futex in slices, between
// which it checks that the peer lives (its pid, stored in the mapping) so that a dead peer reads as
// a closed stream, never a hang. The child reaches the mapping only through the descriptor it
// inherits at spawn, so no other process can, and the link needs no token. Indices the peer wrote
// are checked before use: a corrupt ring (a write index ahead by more than the capacity, a read
// index past the write index) is a kError read or a kIo write, never a wild copy.
//
// Threading: each end is used from one thread at a time; the two ends may live in different
// threads or processes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "host/link/byte_stream.h"
#include "rig/result.h"

namespace hilrig::host {

// Which end of the mapping a stream is: the runner writes ring 0 and reads ring 1.
enum class ShmSide { kRunner = 0, kDut = 1 };

// How long a reader that finds its ring empty spins before it sleeps on the futex: well above a
// lockstep round trip (a few microseconds), well below a scheduler tick. The first
// kShmPauseOnlyNs of it only pause; after that each check also yields the core, so that a peer
// waiting for this very core (a busy host) runs instead of waiting out the spin.
inline constexpr std::int64_t kShmSpinNs = 50'000;
inline constexpr std::int64_t kShmPauseOnlyNs = 5'000;
// Bytes per ring when the caller does not say: many ticks' worth of frames.
inline constexpr std::size_t kShmDefaultRingBytes = std::size_t{1} << 18;

class ShmByteStream final : public ByteStream {
 public:
  // A new mapping with two rings of ring_bytes (a power of two, at least 4 KiB) in a memfd that
  // closes on exec, and the runner's end of it. Fails when the memfd or the mapping cannot be
  // made. shared_fd() is the descriptor to hand the DUT process.
  static rig::Result<std::unique_ptr<ShmByteStream>> Create(
      std::size_t ring_bytes = kShmDefaultRingBytes);
  // `side`'s end of the mapping in `fd` (which the stream then owns and closes). Fails with a
  // message naming the cause when fd is no such mapping (size, magic, ring size).
  static rig::Result<std::unique_ptr<ShmByteStream>> Attach(int fd, ShmSide side);
  // Marks this end closed and wakes the peer, which then reads what is left and sees kClosed.
  ~ShmByteStream() override;
  ShmByteStream(const ShmByteStream&) = delete;
  ShmByteStream& operator=(const ShmByteStream&) = delete;

  // Copies the bytes in as space frees, waiting at most timeout_ms for a full ring to drain.
  // Fails: kLinkClosed (the peer closed or died), kTimeout, kIo (a corrupt read index). No
  // allocation; a system call only to wake a sleeping reader.
  rig::Result<void> WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) override;
  // What the ring holds (up to out.size()), waiting at most timeout_ms (0: never, no spin):
  // kData, kTimeout, kClosed (the peer closed or died and the ring is drained), kError (corrupt
  // write index). No allocation.
  StreamRead ReadSome(std::span<std::uint8_t> out, int timeout_ms) override;
  std::string name() const override;

  // The descriptor of the mapping (owned by this stream), for the DUT process to inherit.
  int shared_fd() const { return fd_; }
  // Times a read slept on the futex, and times a write woke a sleeping reader (the cost a
  // lockstep run should keep near zero).
  std::uint64_t sleeps() const { return sleeps_; }
  std::uint64_t wakes() const { return wakes_; }

  struct Mapping;  // the layout in shared memory (shm_byte_stream.cc)

 private:
  ShmByteStream(int fd, Mapping* mapping, std::size_t ring_bytes, ShmSide side);
  // False when the peer closed its end or its process ended (a poll of its pidfd, which sees a
  // zombie too; kill(2) where pidfds are missing).
  bool PeerAlive();
  // Waits for the read ring to hold data: kData, kTimeout or kClosed.
  StreamStatus WaitReadable(int timeout_ms);
  // Publishes write_pos_ and wakes the reader if it sleeps.
  void Publish();

  int fd_;
  Mapping* mapping_;
  std::size_t ring_bytes_;  // read once at attach: the peer cannot change it under us
  ShmSide side_;
  std::uint64_t write_pos_ = 0;  // this end's copies of its own indices: never read back
  std::uint64_t read_pos_ = 0;
  std::uint64_t seen_read_pos_ = 0;  // the peer's read index of the ring this end writes, as seen
  std::int32_t peer_pid_ = 0;        // whose pidfd peer_pidfd_ is
  int peer_pidfd_ = -1;
  std::uint64_t sleeps_ = 0;
  std::uint64_t wakes_ = 0;
};

}  // namespace hilrig::host
