// The shared-memory transport of the HIL link: both ends in this process (or a forked child for a
// peer that dies), the rings at their smallest size so that wraparound and a full ring come
// quickly. A misbehaving peer is played by a second stream on the same side of the mapping,
// whose own index then contradicts the shared one.
#include "host/link/shm_byte_stream.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <numeric>
#include <thread>
#include <vector>

#include "host/link/hil_link_socket.h"

namespace hilrig::host {
namespace {

constexpr std::size_t kRingBytes = 4096;

struct Pair {
  std::unique_ptr<ShmByteStream> runner;
  std::unique_ptr<ShmByteStream> dut;
};

Pair MakePair() {
  auto runner = ShmByteStream::Create(kRingBytes);
  EXPECT_TRUE(runner.ok()) << runner.error().message;
  auto dut = ShmByteStream::Attach(::dup(runner.value()->shared_fd()), ShmSide::kDut);
  EXPECT_TRUE(dut.ok()) << dut.error().message;
  return {std::move(runner).value(), std::move(dut).value()};
}

std::vector<std::uint8_t> Bytes(std::size_t count, std::uint8_t first) {
  std::vector<std::uint8_t> bytes(count);
  std::iota(bytes.begin(), bytes.end(), first);
  return bytes;
}

// Reads exactly `count` bytes, or what came before the stream stopped giving.
std::vector<std::uint8_t> ReadCount(ByteStream& stream, std::size_t count) {
  std::vector<std::uint8_t> got;
  std::array<std::uint8_t, 1024> chunk;
  while (got.size() < count) {
    const std::size_t want = std::min(chunk.size(), count - got.size());
    const StreamRead read = stream.ReadSome(std::span(chunk.data(), want), 1000);
    if (read.status != StreamStatus::kData) break;
    got.insert(got.end(), chunk.begin(), chunk.begin() + read.bytes);
  }
  return got;
}

TEST(ShmByteStream, CarriesBytesBothWays) {
  Pair pair = MakePair();
  ASSERT_TRUE(pair.runner->WriteAll(Bytes(10, 1), 100).ok());
  ASSERT_TRUE(pair.dut->WriteAll(Bytes(7, 50), 100).ok());
  EXPECT_EQ(ReadCount(*pair.dut, 10), Bytes(10, 1));
  EXPECT_EQ(ReadCount(*pair.runner, 7), Bytes(7, 50));
}

TEST(ShmByteStream, WrapsAroundTheRingEnd) {
  Pair pair = MakePair();
  for (std::uint8_t round = 0; round < 5; ++round) {
    const std::vector<std::uint8_t> bytes = Bytes(3000, round);
    ASSERT_TRUE(pair.runner->WriteAll(bytes, 100).ok());
    ASSERT_EQ(ReadCount(*pair.dut, bytes.size()), bytes) << "round " << int{round};
  }
}

TEST(ShmByteStream, AnEmptyRingTimesOutAtOnceWithoutWaiting) {
  Pair pair = MakePair();
  std::array<std::uint8_t, 16> out;
  EXPECT_EQ(pair.dut->ReadSome(out, 0).status, StreamStatus::kTimeout);
  EXPECT_EQ(pair.dut->ReadSome(out, 30).status, StreamStatus::kTimeout);
}

TEST(ShmByteStream, AFullRingTimesOutTheWriteThenTakesMoreOnceRead) {
  Pair pair = MakePair();
  ASSERT_TRUE(pair.runner->WriteAll(Bytes(kRingBytes, 0), 100).ok());
  auto blocked = pair.runner->WriteAll(Bytes(1, 9), 30);
  ASSERT_FALSE(blocked.ok());
  EXPECT_EQ(blocked.error().code, rig::ErrorCode::kTimeout);
  EXPECT_EQ(ReadCount(*pair.dut, 100).size(), 100u);
  EXPECT_TRUE(pair.runner->WriteAll(Bytes(100, 9), 30).ok());
}

TEST(ShmByteStream, AWriteLargerThanTheRingGoesThroughAsTheReaderDrains) {
  Pair pair = MakePair();
  const std::vector<std::uint8_t> bytes = Bytes(3 * kRingBytes + 5, 3);
  std::vector<std::uint8_t> got;
  std::thread reader([&] { got = ReadCount(*pair.dut, bytes.size()); });
  EXPECT_TRUE(pair.runner->WriteAll(bytes, 2000).ok());
  reader.join();
  EXPECT_EQ(got, bytes);
}

TEST(ShmByteStream, ASleepingReaderWakesForTheWrite) {
  Pair pair = MakePair();
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // well past the spin
    EXPECT_TRUE(pair.runner->WriteAll(Bytes(4, 1), 100).ok());
  });
  const auto start = std::chrono::steady_clock::now();
  std::array<std::uint8_t, 16> out;
  const StreamRead read = pair.dut->ReadSome(out, 5000);
  const auto waited = std::chrono::steady_clock::now() - start;
  writer.join();
  EXPECT_EQ(read.status, StreamStatus::kData);
  EXPECT_EQ(read.bytes, 4u);
  EXPECT_GE(pair.dut->sleeps(), 1u);
  EXPECT_EQ(pair.runner->wakes(), 1u);
  EXPECT_LT(waited, std::chrono::seconds(2));  // woken, not timed out
}

TEST(ShmByteStream, APeerThatClosedIsSeenAfterItsLastBytes) {
  Pair pair = MakePair();
  ASSERT_TRUE(pair.dut->WriteAll(Bytes(3, 1), 100).ok());
  pair.dut.reset();
  EXPECT_EQ(ReadCount(*pair.runner, 3), Bytes(3, 1));
  std::array<std::uint8_t, 16> out;
  EXPECT_EQ(pair.runner->ReadSome(out, 1000).status, StreamStatus::kClosed);
  auto sent = pair.runner->WriteAll(Bytes(3, 1), 100);
  ASSERT_FALSE(sent.ok());
  EXPECT_EQ(sent.error().code, rig::ErrorCode::kLinkClosed);
}

// A child process that attaches the DUT end and dies without closing it, as a killed dut_emu
// would; -1 when fork fails.
pid_t ForkAPeerThatDies(const ShmByteStream& runner) {
  const pid_t child = ::fork();
  if (child == 0) {
    auto dut = ShmByteStream::Attach(::dup(runner.shared_fd()), ShmSide::kDut);
    ::_exit(dut.ok() ? 0 : 1);
  }
  return child;
}

// True when a read on `runner` reports the closed peer well before its timeout.
bool ReadsClosedAtOnce(ShmByteStream& runner) {
  std::array<std::uint8_t, 16> out;
  const auto start = std::chrono::steady_clock::now();
  const StreamStatus status = runner.ReadSome(out, 5000).status;
  return status == StreamStatus::kClosed &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(1);
}

int ExitStatusOf(pid_t child) {
  int status = -1;
  EXPECT_EQ(::waitpid(child, &status, 0), child);
  return status;
}

TEST(ShmByteStream, APeerProcessThatDiedReadsAsClosed) {
  auto runner = ShmByteStream::Create(kRingBytes);
  ASSERT_TRUE(runner.ok());
  const pid_t child = ForkAPeerThatDies(*runner.value());
  ASSERT_GE(child, 0);
  ASSERT_EQ(ExitStatusOf(child), 0);
  EXPECT_TRUE(ReadsClosedAtOnce(*runner.value()));
}

TEST(ShmByteStream, APeerProcessThatDiedUnreapedReadsAsClosed) {
  auto runner = ShmByteStream::Create(kRingBytes);
  ASSERT_TRUE(runner.ok());
  const pid_t child = ForkAPeerThatDies(*runner.value());
  ASSERT_GE(child, 0);
  // Not reaped before the read: a zombie, which kill(pid, 0) would still find.
  EXPECT_TRUE(ReadsClosedAtOnce(*runner.value()));
  EXPECT_EQ(ExitStatusOf(child), 0);
}

TEST(ShmByteStream, AWriteIndexMoreThanARingAheadIsACorruptRing) {
  Pair pair = MakePair();
  ASSERT_TRUE(pair.runner->WriteAll(Bytes(3000, 0), 100).ok());
  ASSERT_EQ(ReadCount(*pair.dut, 3000).size(), 3000u);
  ASSERT_TRUE(pair.runner->WriteAll(Bytes(3000, 0), 100).ok());
  // A second reader on the same ring: its read index restarts at 0, 6000 bytes behind.
  auto rogue = ShmByteStream::Attach(::dup(pair.runner->shared_fd()), ShmSide::kDut);
  ASSERT_TRUE(rogue.ok());
  std::array<std::uint8_t, 16> out;
  const StreamRead read = rogue.value()->ReadSome(out, 100);
  EXPECT_EQ(read.status, StreamStatus::kError);
  EXPECT_NE(read.error.find("corrupt ring"), std::string::npos) << read.error;
}

TEST(ShmByteStream, AReadIndexAheadOfTheWriterIsACorruptRing) {
  Pair pair = MakePair();
  auto rogue = ShmByteStream::Attach(::dup(pair.runner->shared_fd()), ShmSide::kRunner);
  ASSERT_TRUE(rogue.ok());
  ASSERT_TRUE(rogue.value()->WriteAll(Bytes(100, 0), 100).ok());
  ASSERT_EQ(ReadCount(*pair.dut, 100).size(), 100u);
  // Its write index is still 0; the reader's index is consulted once the ring may be full.
  auto sent = pair.runner->WriteAll(Bytes(kRingBytes + 1, 0), 100);
  ASSERT_FALSE(sent.ok());
  EXPECT_EQ(sent.error().code, rig::ErrorCode::kIo);
  EXPECT_NE(sent.error().message.find("corrupt ring"), std::string::npos);
}

TEST(ShmByteStream, AnOversizedFrameLengthIsALinkError) {
  Pair pair = MakePair();
  LinkConnection runner(std::move(pair.runner), "runner");
  LinkConnection dut(std::move(pair.dut), "dut");
  // A varint length prefix of 2^35: far past any frame the codec accepts.
  ASSERT_TRUE(runner.SendBytes(std::string("\x80\x80\x80\x80\x80\x01", 6)).ok());
  const LinkReceived received = dut.Receive(1000);
  EXPECT_EQ(received.status, LinkReceiveStatus::kLinkError);
  EXPECT_EQ(received.link_error, LinkErrorKind::kOversized);
}

TEST(ShmByteStream, CarriesLinkMessages) {
  Pair pair = MakePair();
  LinkConnection runner(std::move(pair.runner), "runner");
  LinkConnection dut(std::move(pair.dut), "dut");
  proto::LinkMessage step;
  step.mutable_step()->set_tick(7);
  step.mutable_step()->add_can_frame(std::string(28, 'x'));
  LinkSequencer sequencer;
  sequencer.Stamp(step, 0);
  ASSERT_TRUE(runner.Send(step).ok());
  const LinkReceived received = dut.Receive(1000);
  ASSERT_EQ(received.status, LinkReceiveStatus::kMessage) << received.error;
  EXPECT_EQ(received.message.step().tick(), 7u);
  EXPECT_EQ(received.message.step().can_frame(0), std::string(28, 'x'));
}

TEST(ShmByteStream, RefusesADescriptorThatIsNoLinkMapping) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  ::close(pipe_fds[1]);
  EXPECT_FALSE(ShmByteStream::Attach(pipe_fds[0], ShmSide::kDut).ok());
  EXPECT_FALSE(ShmByteStream::Create(1000).ok());  // not a power of two
}

}  // namespace
}  // namespace hilrig::host
