// UdpBus is a CAN bus made of UDP datagrams on the loopback interface, so that the host and a
// DUT in another process (or several) share one bus without CAN hardware or kernel support. Each
// endpoint owns a UDP socket bound to address:base_port + node_index, and the bus is the set of
// ports base_port .. base_port + node_count - 1: Send writes one datagram per frame to every
// other port, and to its own too when the endpoint receives its own frames, so that the echo
// passes through the same socket queue as everyone else's frames and keeps their order.
//
// Wire format (little-endian, 20-byte header then the payload; a remote frame carries none):
//   0  u32 magic 'HCAN' (0x4E414348)    4  u8 version (1)    5  u8 flags (CanFrame bools:
//   bit0 extended, bit1 remote, bit2 error, bit3 fd, bit4 brs, bit5 esi)    6  u8 length
//   7  u8 reserved (0)    8  u32 id    12  i64 sender time in ns    20  payload
// A datagram that is short, long, of another magic or version, with unknown flag or reserved
// bits, a payload size that disagrees with its length, or a frame ValidateFrame refuses is
// counted in frames_dropped_malformed and dropped. A well-formed one whose source is not one of the
// bus's ports on the bus's address is counted in frames_dropped_foreign and dropped: any process on
// the host may send to a loopback port, but only the members hold the bus's ports (a bus bound to
// a wildcard address takes its members' ports from any address).
//
// Time: Receive is a non-blocking poll of the socket, and every frame it returns is stamped with
// the now_ns passed to it, i.e. "arrived by the time this endpoint looked". The sender's time
// travels in the datagram but is not used for the stamp, because the two processes do not share
// one clock. There is no wire timing, arbitration or error confinement: the bus is always
// error-active and as fast as the loopback interface.
//
// Only the loopback address is bound by default, so the bus is not reachable from the network;
// binding another address is an explicit configuration choice.
//
// Threading: one endpoint is used from one thread at a time, like the other backends.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rig/can_bus.h"
#include "rig/result.h"

namespace hilrig::rig {

inline constexpr std::uint32_t kUdpCanMagic = 0x4E414348;  // "HCAN" in little-endian bytes
inline constexpr std::uint8_t kUdpCanVersion = 1;
inline constexpr std::size_t kUdpCanHeaderBytes = 20;
inline constexpr std::size_t kUdpCanMaxDatagramBytes = kUdpCanHeaderBytes + CanFrame::kMaxFdPayload;

struct UdpBusConfig {
  std::string address = "127.0.0.1";
  std::uint16_t base_port = 0;
  std::size_t node_count = 2;  // the bus is ports base_port .. base_port + node_count - 1
  std::size_t node_index = 0;  // this endpoint binds base_port + node_index
};

// The datagram for a frame; the frame must be valid. Returns the bytes written into `out`.
std::size_t EncodeUdpCanDatagram(const CanFrame& frame, std::int64_t sender_time_ns,
                                 std::span<std::uint8_t, kUdpCanMaxDatagramBytes> out);
struct UdpCanDatagram {
  CanFrame frame;
  std::int64_t sender_time_ns = 0;
};
Result<UdpCanDatagram> DecodeUdpCanDatagram(std::span<const std::uint8_t> datagram);

class UdpBus final : public CanBus {
 public:
  // Fails on a bad config or a port that cannot be bound (e.g. already in use).
  static Result<std::unique_ptr<UdpBus>> Open(const UdpBusConfig& config);
  ~UdpBus() override;
  UdpBus(const UdpBus&) = delete;
  UdpBus& operator=(const UdpBus&) = delete;

  // Fails on an invalid frame, or if the datagram could not be handed to some peer's port (the
  // others still get it; UDP has no transaction).
  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override;
  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override;
  void SetFilters(std::span<const CanFilter> filters) override;
  void SetReceiveErrorFrames(bool enabled) override;
  void SetErrorFrameMask(std::uint32_t class_mask) override;
  Result<void> SetReceiveOwnFrames(bool enabled) override;
  BusState state() const override { return BusState::kErrorActive; }
  BusCounters counters() const override { return counters_; }

  std::uint16_t local_port() const;
  // The address the socket is actually bound to, as the kernel reports it (e.g. "127.0.0.1").
  std::string local_address() const;

 private:
  struct Socket;  // keeps Boost.Asio out of this header
  explicit UdpBus(std::unique_ptr<Socket> socket);

  // One datagram from the socket, or false when none is waiting.
  bool ReceiveOne(std::int64_t now_ns, std::vector<TimedCanFrame>& out);

  std::unique_ptr<Socket> socket_;
  std::vector<CanFilter> filters_;
  std::uint32_t error_mask_ = 0;
  bool receive_own_frames_ = false;
  BusCounters counters_;
};

// All node_count endpoints of one bus inside this process, on the first range of free ports
// from first_base_port on (trying up to `attempts` ranges, node_count apart). first_base_port 0
// starts at a random port in 20000..59999 (from the kernel, so that no other process can tell the
// bus's ports in advance, and processes running in parallel rarely try the same ones). Processes
// sharing a bus each open their own node with UdpBus::Open.
Result<std::vector<std::unique_ptr<UdpBus>>> OpenUdpBusGroup(std::size_t node_count,
                                                             std::uint16_t first_base_port = 0,
                                                             int attempts = 64);

}  // namespace hilrig::rig
