#include "host/link/shm_byte_stream.h"

#include <linux/futex.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <new>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace hilrig::host {
namespace {

constexpr std::uint64_t kMagic = 0x6b6e696c2d6c6968ULL;  // "hil-link"
constexpr std::size_t kMinRingBytes = 4096;
constexpr std::size_t kPageBytes = 4096;
// A sleeping reader wakes this often to check that the peer lives.
constexpr std::int64_t kSleepSliceNs = 10'000'000;
constexpr int kSpinChecksEvery = 64;  // pause iterations between clock reads while spinning
const timespec kFullRingNap{0, 20'000};

// One direction: the writer owns write_pos, the reader read_pos and reader_sleeping (the futex
// word), each on a cache line of its own so that the two ends do not false-share.
struct Ring {
  alignas(64) std::atomic<std::uint64_t> write_pos{0};
  alignas(64) std::atomic<std::uint64_t> read_pos{0};
  alignas(64) std::atomic<std::uint32_t> reader_sleeping{0};
};

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

void Pause() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// The OS's clock, not an injected one: the waits it bounds spin on the CPU and sleep in the
// kernel's futex, whose timeout runs on this clock, to bound how long the peer process may take.
std::int64_t SteadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

long Futex(std::atomic<std::uint32_t>& word, int op, std::uint32_t value, const timespec* timeout) {
  return ::syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, value, timeout, nullptr,
                   0);
}

int Index(ShmSide side) { return static_cast<int>(side); }
int Peer(ShmSide side) { return 1 - Index(side); }

std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

struct ShmByteStream::Mapping {
  std::uint64_t magic = kMagic;
  std::uint64_t ring_bytes = 0;
  std::atomic<std::int32_t> pid[2] = {0, 0};      // by ShmSide; 0 until that end attaches
  std::atomic<std::uint32_t> closed[2] = {0, 0};  // by ShmSide
  Ring rings[2];                                  // by the ShmSide that writes it
};

namespace {

std::size_t DataOffset() {
  return (sizeof(ShmByteStream::Mapping) + kPageBytes - 1) / kPageBytes * kPageBytes;
}

std::uint8_t* RingData(ShmByteStream::Mapping* mapping, std::size_t ring_bytes, int ring) {
  return reinterpret_cast<std::uint8_t*>(mapping) + DataOffset() + ring * ring_bytes;
}

}  // namespace

ShmByteStream::ShmByteStream(int fd, Mapping* mapping, std::size_t ring_bytes, ShmSide side)
    : fd_(fd), mapping_(mapping), ring_bytes_(ring_bytes), side_(side) {
  mapping_->pid[Index(side_)].store(static_cast<std::int32_t>(::getpid()));
}

rig::Result<std::unique_ptr<ShmByteStream>> ShmByteStream::Create(std::size_t ring_bytes) {
  if (ring_bytes < kMinRingBytes || (ring_bytes & (ring_bytes - 1)) != 0) {
    return rig::MakeError("shm link ring of " + std::to_string(ring_bytes) +
                          " bytes: must be a power of two of at least 4096");
  }
  const int fd = ::memfd_create("hilrig-link", MFD_CLOEXEC);
  if (fd < 0) return rig::MakeError(rig::ErrorCode::kIo, Errno("shm link memfd_create"));
  const std::size_t bytes = DataOffset() + 2 * ring_bytes;
  if (::ftruncate(fd, static_cast<off_t>(bytes)) != 0) {
    auto error = rig::MakeError(rig::ErrorCode::kIo, Errno("shm link ftruncate"));
    ::close(fd);
    return error;
  }
  void* memory = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (memory == MAP_FAILED) {
    auto error = rig::MakeError(rig::ErrorCode::kIo, Errno("shm link mmap"));
    ::close(fd);
    return error;
  }
  auto* mapping = new (memory) Mapping;
  mapping->ring_bytes = ring_bytes;
  return std::unique_ptr<ShmByteStream>(
      new ShmByteStream(fd, mapping, ring_bytes, ShmSide::kRunner));
}

rig::Result<std::unique_ptr<ShmByteStream>> ShmByteStream::Attach(int fd, ShmSide side) {
  const std::string what = "shm link fd " + std::to_string(fd);
  const auto fail = [fd](rig::Error error) {
    ::close(fd);
    return error;
  };
  struct stat status {};
  if (::fstat(fd, &status) != 0) return fail(rig::MakeError(rig::ErrorCode::kIo, Errno(what)));
  const auto bytes = static_cast<std::size_t>(status.st_size);
  if (bytes < DataOffset() + 2 * kMinRingBytes) {
    return fail(rig::MakeError(what + ": " + std::to_string(bytes) + " bytes, too small"));
  }
  void* memory = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (memory == MAP_FAILED) return fail(rig::MakeError(rig::ErrorCode::kIo, Errno(what + " mmap")));
  auto* mapping = static_cast<Mapping*>(memory);
  const std::uint64_t ring_bytes = mapping->ring_bytes;
  if (mapping->magic != kMagic || ring_bytes < kMinRingBytes ||
      (ring_bytes & (ring_bytes - 1)) != 0 || DataOffset() + 2 * ring_bytes != bytes) {
    ::munmap(memory, bytes);
    return fail(rig::MakeError(what + ": not a HIL link mapping (bad magic or ring size)"));
  }
  return std::unique_ptr<ShmByteStream>(new ShmByteStream(fd, mapping, ring_bytes, side));
}

ShmByteStream::~ShmByteStream() {
  mapping_->closed[Index(side_)].store(1);
  // The peer reads the ring this end writes; a sleeping peer must see the close now.
  Ring& ring = mapping_->rings[Index(side_)];
  if (ring.reader_sleeping.exchange(0) != 0) Futex(ring.reader_sleeping, FUTEX_WAKE, 1, nullptr);
  ::munmap(mapping_, DataOffset() + 2 * ring_bytes_);
  ::close(fd_);
  if (peer_pidfd_ >= 0) ::close(peer_pidfd_);
}

std::string ShmByteStream::name() const {
  return std::string("shm link (") + (side_ == ShmSide::kRunner ? "runner" : "dut") + " end)";
}

bool ShmByteStream::PeerAlive() {
  if (mapping_->closed[Peer(side_)].load() != 0) return false;
  const std::int32_t pid = mapping_->pid[Peer(side_)].load();
  // Not attached yet counts as alive: the runner's watchdog covers a child that never attaches.
  if (pid <= 0) return true;
  if (pid != peer_pid_) {
    if (peer_pidfd_ >= 0) ::close(peer_pidfd_);
    peer_pid_ = pid;
    peer_pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  }
  // A pidfd turns readable when the process ends, even while nobody has reaped it (a zombie
  // still answers kill); without pidfds (before Linux 5.3) kill is the probe.
  if (peer_pidfd_ < 0) return ::kill(pid, 0) == 0 || errno != ESRCH;
  pollfd ended{peer_pidfd_, POLLIN, 0};
  return ::poll(&ended, 1, 0) == 0;
}

void ShmByteStream::Publish() {
  Ring& ring = mapping_->rings[Index(side_)];
  // Sequentially consistent store, then load: with the reader's store of reader_sleeping and its
  // load of write_pos, one of the two sees the other, so a wake is never lost.
  ring.write_pos.store(write_pos_);
  if (ring.reader_sleeping.load() != 0 && ring.reader_sleeping.exchange(0) != 0) {
    Futex(ring.reader_sleeping, FUTEX_WAKE, 1, nullptr);
    ++wakes_;
  }
}

rig::Result<void> ShmByteStream::WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) {
  if (mapping_->closed[Peer(side_)].load() != 0) {
    return rig::MakeError(rig::ErrorCode::kLinkClosed, name() + ": closed by the peer");
  }
  Ring& ring = mapping_->rings[Index(side_)];
  std::uint8_t* data = RingData(mapping_, ring_bytes_, Index(side_));
  std::int64_t deadline_ns = -1;  // read from the clock only once the ring is full
  std::size_t done = 0;
  while (done < bytes.size()) {
    // The reader's index is read again only when the copy seen last leaves too little space:
    // most writes then touch no cache line the reader wrote.
    if (ring_bytes_ - (write_pos_ - seen_read_pos_) < bytes.size() - done) {
      seen_read_pos_ = ring.read_pos.load(std::memory_order_acquire);
    }
    const std::uint64_t read_pos = seen_read_pos_;
    const std::uint64_t used = write_pos_ - read_pos;  // wraps huge when read_pos is ahead
    if (used > ring_bytes_) {
      return rig::MakeError(rig::ErrorCode::kIo,
                            name() + ": corrupt ring: read index " + std::to_string(read_pos) +
                                " does not fit write index " + std::to_string(write_pos_));
    }
    const std::size_t space = ring_bytes_ - used;
    if (space == 0) {
      if (!PeerAlive()) {
        return rig::MakeError(rig::ErrorCode::kLinkClosed, name() + ": the peer is gone");
      }
      const std::int64_t now_ns = SteadyNs();
      if (deadline_ns < 0) deadline_ns = now_ns + std::int64_t{timeout_ms} * 1'000'000;
      if (now_ns >= deadline_ns) {
        return rig::MakeError(rig::ErrorCode::kTimeout, name() + ": write timed out after " +
                                                            std::to_string(timeout_ms) +
                                                            " ms (the peer does not read)");
      }
      ::nanosleep(&kFullRingNap, nullptr);
      continue;
    }
    const std::size_t n = std::min(space, bytes.size() - done);
    const std::size_t at = write_pos_ & (ring_bytes_ - 1);
    const std::size_t first = std::min(n, ring_bytes_ - at);
    std::memcpy(data + at, bytes.data() + done, first);
    std::memcpy(data, bytes.data() + done + first, n - first);
    write_pos_ += n;
    done += n;
    Publish();
  }
  return {};
}

StreamStatus ShmByteStream::WaitReadable(int timeout_ms) {
  Ring& ring = mapping_->rings[Peer(side_)];
  const auto has_data = [&] { return ring.write_pos.load(std::memory_order_acquire) != read_pos_; };
  const std::int64_t start_ns = timeout_ms > 0 ? SteadyNs() : 0;
  if (timeout_ms > 0) {
    for (int spins = 1;; ++spins) {
      if (has_data()) return StreamStatus::kData;
      Pause();
      if (spins % kSpinChecksEvery != 0) continue;
      const std::int64_t spun_ns = SteadyNs() - start_ns;
      if (spun_ns >= kShmSpinNs) break;
      // Past a round trip's worth the peer is likely waiting for a core, maybe this one.
      if (spun_ns >= kShmPauseOnlyNs) ::sched_yield();
    }
  }
  const std::int64_t deadline_ns = start_ns + std::int64_t{timeout_ms} * 1'000'000;
  while (true) {
    if (!PeerAlive()) return has_data() ? StreamStatus::kData : StreamStatus::kClosed;
    const std::int64_t left_ns = timeout_ms > 0 ? deadline_ns - SteadyNs() : 0;
    if (left_ns <= 0) return StreamStatus::kTimeout;
    ring.reader_sleeping.store(1);
    if (ring.write_pos.load() != read_pos_) {
      ring.reader_sleeping.store(0);
      return StreamStatus::kData;
    }
    const std::int64_t slice_ns = std::min(left_ns, kSleepSliceNs);
    const timespec slice{static_cast<time_t>(slice_ns / 1'000'000'000),
                         static_cast<long>(slice_ns % 1'000'000'000)};
    Futex(ring.reader_sleeping, FUTEX_WAIT, 1, &slice);
    ++sleeps_;
    ring.reader_sleeping.store(0);
    if (has_data()) return StreamStatus::kData;
  }
}

StreamRead ShmByteStream::ReadSome(std::span<std::uint8_t> out, int timeout_ms) {
  Ring& ring = mapping_->rings[Peer(side_)];
  std::uint64_t write_pos = ring.write_pos.load(std::memory_order_acquire);
  if (write_pos == read_pos_) {
    const StreamStatus status = WaitReadable(timeout_ms);
    if (status == StreamStatus::kClosed) return {status, 0, name() + ": closed by the peer"};
    if (status != StreamStatus::kData) return {status, 0, {}};
    write_pos = ring.write_pos.load(std::memory_order_acquire);
  }
  const std::uint64_t available = write_pos - read_pos_;  // wraps huge when write_pos is behind
  if (available > ring_bytes_) {
    return {StreamStatus::kError, 0,
            name() + ": corrupt ring: write index " + std::to_string(write_pos) +
                " does not fit read index " + std::to_string(read_pos_)};
  }
  const std::uint8_t* data = RingData(mapping_, ring_bytes_, Peer(side_));
  const std::size_t n = std::min<std::size_t>(available, out.size());
  const std::size_t at = read_pos_ & (ring_bytes_ - 1);
  const std::size_t first = std::min(n, ring_bytes_ - at);
  std::memcpy(out.data(), data + at, first);
  std::memcpy(out.data() + first, data, n - first);
  read_pos_ += n;
  ring.read_pos.store(read_pos_, std::memory_order_release);
  return {StreamStatus::kData, n, {}};
}

}  // namespace hilrig::host
