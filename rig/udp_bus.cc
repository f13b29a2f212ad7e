#include "rig/udp_bus.h"

#include <algorithm>
#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <limits>
#include <string>
#include <utility>

#include "rig/os_random.h"

namespace hilrig::rig {
namespace {

namespace asio = boost::asio;
using asio::ip::udp;

enum FlagBit : std::uint8_t {
  kExtended = 1u << 0,
  kRemote = 1u << 1,
  kError = 1u << 2,
  kFd = 1u << 3,
  kBitrateSwitch = 1u << 4,
  kErrorStateIndicator = 1u << 5,
};
constexpr std::uint8_t kKnownFlags = 0x3F;

void PutLe(std::uint8_t* out, std::uint64_t value, std::size_t bytes) {
  for (std::size_t i = 0; i < bytes; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

std::uint64_t GetLe(const std::uint8_t* in, std::size_t bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes; ++i) value |= std::uint64_t{in[i]} << (8 * i);
  return value;
}

std::uint8_t FlagsOf(const CanFrame& frame) {
  return (frame.extended ? kExtended : 0) | (frame.remote ? kRemote : 0) |
         (frame.error ? kError : 0) | (frame.fd ? kFd : 0) |
         (frame.bitrate_switch ? kBitrateSwitch : 0) |
         (frame.error_state_indicator ? kErrorStateIndicator : 0);
}

void ApplyFlags(std::uint8_t flags, CanFrame& frame) {
  frame.extended = (flags & kExtended) != 0;
  frame.remote = (flags & kRemote) != 0;
  frame.error = (flags & kError) != 0;
  frame.fd = (flags & kFd) != 0;
  frame.bitrate_switch = (flags & kBitrateSwitch) != 0;
  frame.error_state_indicator = (flags & kErrorStateIndicator) != 0;
}

Result<void> CheckConfig(const UdpBusConfig& config) {
  if (config.node_count == 0 || config.node_index >= config.node_count) {
    return MakeError("UdpBus node_index " + std::to_string(config.node_index) +
                     " is not below node_count " + std::to_string(config.node_count));
  }
  if (config.base_port == 0 ||
      config.base_port + config.node_count - 1 > std::numeric_limits<std::uint16_t>::max()) {
    return MakeError("UdpBus ports " + std::to_string(config.base_port) + " + 0.." +
                     std::to_string(config.node_count - 1) + " are not all valid UDP ports");
  }
  return {};
}

}  // namespace

std::size_t EncodeUdpCanDatagram(const CanFrame& frame, std::int64_t sender_time_ns,
                                 std::span<std::uint8_t, kUdpCanMaxDatagramBytes> out) {
  HILRIG_CHECK(ValidateFrame(frame).ok(), "EncodeUdpCanDatagram needs a valid frame");
  PutLe(&out[0], kUdpCanMagic, 4);
  out[4] = kUdpCanVersion;
  out[5] = FlagsOf(frame);
  out[6] = frame.length;
  out[7] = 0;
  PutLe(&out[8], frame.id, 4);
  PutLe(&out[12], static_cast<std::uint64_t>(sender_time_ns), 8);
  const std::span<const std::uint8_t> payload = frame.payload();
  std::copy(payload.begin(), payload.end(), out.begin() + kUdpCanHeaderBytes);
  return kUdpCanHeaderBytes + payload.size();
}

Result<UdpCanDatagram> DecodeUdpCanDatagram(std::span<const std::uint8_t> datagram) {
  if (datagram.size() < kUdpCanHeaderBytes) return MakeError("datagram shorter than its header");
  if (datagram.size() > kUdpCanMaxDatagramBytes) return MakeError("datagram longer than a frame");
  if (GetLe(&datagram[0], 4) != kUdpCanMagic) return MakeError("not a CAN datagram (magic)");
  if (datagram[4] != kUdpCanVersion) {
    return MakeError("CAN datagram version " + std::to_string(datagram[4]) + " not supported");
  }
  if ((datagram[5] & ~kKnownFlags) != 0 || datagram[7] != 0) {
    return MakeError("CAN datagram with unknown flag or reserved bits");
  }
  UdpCanDatagram decoded;
  CanFrame& frame = decoded.frame;
  ApplyFlags(datagram[5], frame);
  frame.length = datagram[6];
  frame.id = static_cast<std::uint32_t>(GetLe(&datagram[8], 4));
  decoded.sender_time_ns = static_cast<std::int64_t>(GetLe(&datagram[12], 8));
  if (Result<void> valid = ValidateFrame(frame); !valid) {
    return MakeError("CAN datagram with an invalid frame: " + valid.error().message);
  }
  const std::size_t payload_bytes = frame.payload().size();
  if (datagram.size() != kUdpCanHeaderBytes + payload_bytes) {
    return MakeError("CAN datagram size disagrees with its length field");
  }
  std::copy_n(datagram.begin() + kUdpCanHeaderBytes, payload_bytes, frame.data.begin());
  return decoded;
}

struct UdpBus::Socket {
  asio::io_context io;
  udp::socket socket{io};
  std::vector<udp::endpoint> peers;  // every port of the bus, this endpoint's own included
  udp::endpoint local;
  std::uint16_t base_port = 0;
  std::size_t node_count = 0;

  // A socket bound to a wildcard address sees its own datagrams come from 127.0.0.1.
  bool FromBusAddress(const udp::endpoint& sender) const {
    return local.address().is_unspecified() || sender.address() == local.address();
  }
  bool IsOwn(const udp::endpoint& sender) const {
    return sender.port() == local.port() && FromBusAddress(sender);
  }
  // The bus's ports are one range: a comparison, whatever the node count.
  bool IsMember(const udp::endpoint& sender) const {
    return sender.port() >= base_port &&
           static_cast<std::size_t>(sender.port() - base_port) < node_count &&
           FromBusAddress(sender);
  }
};

Result<std::unique_ptr<UdpBus>> UdpBus::Open(const UdpBusConfig& config) {
  if (Result<void> valid = CheckConfig(config); !valid) return valid.error();
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(config.address, error);
  if (error) return MakeError("UdpBus address " + config.address + ": " + error.message());
  auto socket = std::make_unique<Socket>();
  for (std::size_t k = 0; k < config.node_count; ++k) {
    socket->peers.emplace_back(address, static_cast<std::uint16_t>(config.base_port + k));
  }
  socket->local = socket->peers[config.node_index];
  socket->base_port = config.base_port;
  socket->node_count = config.node_count;
  const auto fail = [&](const std::string& what) -> Result<std::unique_ptr<UdpBus>> {
    return MakeError("UdpBus " + what + " " + socket->local.address().to_string() + ":" +
                     std::to_string(socket->local.port()) + ": " + error.message());
  };
  if (socket->socket.open(socket->local.protocol(), error)) return fail("open");
  if (socket->socket.bind(socket->local, error)) return fail("bind");
  if (socket->socket.non_blocking(true, error)) return fail("set non-blocking on");
  return std::unique_ptr<UdpBus>(new UdpBus(std::move(socket)));
}

UdpBus::UdpBus(std::unique_ptr<Socket> socket) : socket_(std::move(socket)) {}
UdpBus::~UdpBus() = default;

std::uint16_t UdpBus::local_port() const { return socket_->local.port(); }

std::string UdpBus::local_address() const {
  boost::system::error_code error;
  const udp::endpoint bound = socket_->socket.local_endpoint(error);
  return error ? std::string() : bound.address().to_string();
}

Result<void> UdpBus::Send(const CanFrame& frame, std::int64_t now_ns) {
  if (Result<void> valid = ValidateFrame(frame); !valid) {
    ++counters_.send_failures;
    return MakeError("UdpBus: " + valid.error().message);
  }
  std::array<std::uint8_t, kUdpCanMaxDatagramBytes> datagram;
  const std::size_t size = EncodeUdpCanDatagram(frame, now_ns, datagram);
  std::size_t peers = 0;
  std::size_t failed_peers = 0;
  boost::system::error_code error;
  boost::system::error_code last_error;
  for (const udp::endpoint& peer : socket_->peers) {
    if (peer == socket_->local && !receive_own_frames_) continue;  // an echo nobody wants
    socket_->socket.send_to(asio::buffer(datagram.data(), size), peer, 0, error);
    ++peers;
    if (error) {
      ++failed_peers;
      last_error = error;
    }
  }
  if (failed_peers > 0) {
    ++counters_.send_failures;
    return MakeError("UdpBus: frame not delivered to " + std::to_string(failed_peers) + " of " +
                     std::to_string(peers) + " ports: " + last_error.message());
  }
  ++counters_.frames_sent;
  return {};
}

std::size_t UdpBus::Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) {
  const std::size_t before = out.size();
  while (ReceiveOne(now_ns, out)) {
  }
  const std::size_t appended = out.size() - before;
  counters_.frames_received += appended;
  return appended;
}

bool UdpBus::ReceiveOne(std::int64_t now_ns, std::vector<TimedCanFrame>& out) {
  // One byte more than the largest valid datagram, so that an oversized one shows as such
  // instead of being silently truncated into something that parses.
  std::array<std::uint8_t, kUdpCanMaxDatagramBytes + 1> buffer;
  udp::endpoint sender;
  boost::system::error_code error;
  const std::size_t size = socket_->socket.receive_from(asio::buffer(buffer), sender, 0, error);
  if (error == asio::error::would_block || error == asio::error::try_again) return false;
  // An ICMP port-unreachable for an earlier send surfaces here; it says nothing about this read.
  if (error == asio::error::connection_refused) return true;
  if (error) return false;
  Result<UdpCanDatagram> decoded = DecodeUdpCanDatagram({buffer.data(), size});
  if (!decoded) {
    ++counters_.frames_dropped_malformed;
    return true;
  }
  if (!socket_->IsMember(sender)) {
    ++counters_.frames_dropped_foreign;
    return true;
  }
  const CanFrame& frame = decoded.value().frame;
  const bool own_frame = socket_->IsOwn(sender);
  if (own_frame && !receive_own_frames_) return true;
  const bool wanted = frame.error ? (frame.id & error_mask_) != 0 : FilterAccepts(filters_, frame);
  if (wanted) out.push_back({frame, now_ns, own_frame});
  return true;
}

void UdpBus::SetFilters(std::span<const CanFilter> filters) {
  filters_.assign(filters.begin(), filters.end());
}

void UdpBus::SetReceiveErrorFrames(bool enabled) { error_mask_ = enabled ? kCanErrMask : 0; }

void UdpBus::SetErrorFrameMask(std::uint32_t class_mask) { error_mask_ = class_mask; }

Result<void> UdpBus::SetReceiveOwnFrames(bool enabled) {
  receive_own_frames_ = enabled;
  return {};
}

namespace {

Result<std::vector<std::unique_ptr<UdpBus>>> OpenGroupAt(std::size_t node_count,
                                                         std::uint16_t base_port) {
  std::vector<std::unique_ptr<UdpBus>> endpoints;
  for (std::size_t k = 0; k < node_count; ++k) {
    Result<std::unique_ptr<UdpBus>> endpoint =
        UdpBus::Open({.base_port = base_port, .node_count = node_count, .node_index = k});
    if (!endpoint) return endpoint.error();
    endpoints.push_back(std::move(endpoint).value());
  }
  return endpoints;
}

}  // namespace

Result<std::vector<std::unique_ptr<UdpBus>>> OpenUdpBusGroup(std::size_t node_count,
                                                             std::uint16_t first_base_port,
                                                             int attempts) {
  std::size_t base_port = first_base_port;
  if (base_port == 0) {
    std::array<std::uint8_t, 4> random{};
    if (Result<void> filled = FillWithOsRandomBytes(random); !filled) {
      return MakeError("no random port for the UDP bus: " + filled.error().message);
    }
    base_port = 20'000 + static_cast<std::size_t>(GetLe(random.data(), random.size()) % 40'000);
  }
  std::string last_error = "no attempt made";
  for (int attempt = 0; attempt < attempts; ++attempt, base_port += node_count) {
    if (base_port + node_count - 1 > std::numeric_limits<std::uint16_t>::max()) break;
    auto endpoints = OpenGroupAt(node_count, static_cast<std::uint16_t>(base_port));
    if (endpoints) return endpoints;
    last_error = endpoints.error().message;
  }
  return MakeError("no free range of " + std::to_string(node_count) + " UDP ports after " +
                   std::to_string(attempts) + " attempts; last: " + last_error);
}

}  // namespace hilrig::rig
