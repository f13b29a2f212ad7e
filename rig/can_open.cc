#include "rig/can_open.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "rig/command_args.h"
#include "rig/emulated_bus.h"
#include "rig/gs_usb_bus.h"
#include "rig/libusb_gs_usb_transport.h"
#include "rig/socketcan_bus.h"

namespace hilrig::rig {
namespace {

constexpr const char* kUriForms =
    "expected emulated, udp:BASE_PORT[:INDEX[:COUNT]], socketcan:IFACE or gs_usb[:SERIAL]";

Error UriError(const std::string& uri, const std::string& problem) {
  return MakeError("CAN bus \"" + uri + "\": " + problem);
}

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = text.find(separator, start);
    parts.push_back(text.substr(start, at - start));
    if (at == std::string::npos) return parts;
    start = at + 1;
  }
}

template <typename T>
Result<T> ParseUriNumber(const std::string& uri, const std::string& text, const std::string& what) {
  auto value = ParseNumber<T>(text, what);
  if (!value) return UriError(uri, value.error().message);
  return value;
}

Result<CanBusUri> ParseUdp(const std::string& uri, const std::vector<std::string>& parts) {
  if (parts.size() < 2 || parts.size() > 4) {
    return UriError(uri, "expected udp:BASE_PORT[:INDEX[:COUNT]]");
  }
  CanBusUri parsed;
  parsed.scheme = CanBusUri::Scheme::kUdp;
  auto port = ParseUriNumber<std::uint16_t>(uri, parts[1], "UDP base port");
  if (!port) return port.error();
  parsed.udp.base_port = port.value();
  parsed.udp.node_index = 1;
  if (parts.size() >= 3) {
    auto index = ParseUriNumber<std::size_t>(uri, parts[2], "UDP node index");
    if (!index) return index.error();
    parsed.udp.node_index = index.value();
  }
  if (parts.size() == 4) {
    auto count = ParseUriNumber<std::size_t>(uri, parts[3], "UDP node count");
    if (!count) return count.error();
    parsed.udp.node_count = count.value();
  }
  if (parsed.udp.base_port == 0) return UriError(uri, "UDP base port 0");
  if (parsed.udp.node_index >= parsed.udp.node_count) {
    return UriError(uri, "UDP node index not below node count");
  }
  return parsed;
}

// A lone node that owns its emulated bus; the endpoint goes before the bus it points into.
class LoneEmulatedNode final : public CanBus {
 public:
  LoneEmulatedNode() : endpoint_(bus_.Connect("emulated")) {}
  ~LoneEmulatedNode() override { endpoint_.reset(); }

  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override {
    return endpoint_->Send(frame, now_ns);
  }
  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override {
    return endpoint_->Receive(now_ns, out);
  }
  void SetFilters(std::span<const CanFilter> filters) override { endpoint_->SetFilters(filters); }
  void SetReceiveErrorFrames(bool enabled) override { endpoint_->SetReceiveErrorFrames(enabled); }
  void SetErrorFrameMask(std::uint32_t class_mask) override {
    endpoint_->SetErrorFrameMask(class_mask);
  }
  Result<void> SetReceiveOwnFrames(bool enabled) override {
    return endpoint_->SetReceiveOwnFrames(enabled);
  }
  BusState state() const override { return endpoint_->state(); }
  BusCounters counters() const override { return endpoint_->counters(); }

 private:
  EmulatedBus bus_;
  std::unique_ptr<CanBus> endpoint_;
};

template <typename Bus>
Result<std::unique_ptr<CanBus>> AsCanBus(Result<std::unique_ptr<Bus>> bus) {
  if (!bus) return bus.error();
  return std::unique_ptr<CanBus>(std::move(bus).value());
}

Result<std::unique_ptr<CanBus>> OpenGsUsbAdapter(const std::string& usb_serial,
                                                 const GsUsbTransportOpener& open_transport) {
  auto transport = open_transport ? open_transport(usb_serial)
                                  : OpenLibusbGsUsbTransport(kKnownGsUsbDevices, usb_serial);
  if (!transport) return transport.error();
  return AsCanBus(GsUsbBus::Open(std::move(transport).value(), GsUsbOptions{}));
}

}  // namespace

Result<CanBusUri> ParseCanBusUri(const std::string& uri) {
  const std::vector<std::string> parts = Split(uri, ':');
  const std::string& scheme = parts[0];
  CanBusUri parsed;
  if (scheme == "emulated") {
    if (parts.size() != 1) return UriError(uri, "emulated takes no arguments");
    return parsed;
  }
  if (scheme == "udp") return ParseUdp(uri, parts);
  if (scheme == "socketcan") {
    if (parts.size() != 2 || parts[1].empty()) {
      return UriError(uri, "expected socketcan:IFACE with one interface name");
    }
    parsed.scheme = CanBusUri::Scheme::kSocketCan;
    parsed.interface = parts[1];
    return parsed;
  }
  if (scheme == "gs_usb") {
    if (parts.size() > 2 || (parts.size() == 2 && parts[1].empty())) {
      return UriError(uri, "expected gs_usb or gs_usb:SERIAL");
    }
    parsed.scheme = CanBusUri::Scheme::kGsUsb;
    if (parts.size() == 2) parsed.usb_serial = parts[1];
    return parsed;
  }
  return UriError(uri, "unknown scheme \"" + scheme + "\"; " + kUriForms);
}

Result<std::unique_ptr<CanBus>> OpenCanBus(const CanBusUri& uri,
                                           const GsUsbTransportOpener& open_gs_usb) {
  switch (uri.scheme) {
    case CanBusUri::Scheme::kEmulated:
      return std::unique_ptr<CanBus>(std::make_unique<LoneEmulatedNode>());
    case CanBusUri::Scheme::kUdp:
      return AsCanBus(UdpBus::Open(uri.udp));
    case CanBusUri::Scheme::kSocketCan:
      return AsCanBus(OpenSocketCan(uri.interface));
    case CanBusUri::Scheme::kGsUsb:
      return OpenGsUsbAdapter(uri.usb_serial, open_gs_usb);
  }
  return MakeError("unknown CAN bus scheme");
}

Result<std::unique_ptr<CanBus>> OpenCanBus(const std::string& uri,
                                           const GsUsbTransportOpener& open_gs_usb) {
  auto parsed = ParseCanBusUri(uri);
  if (!parsed) return parsed.error();
  auto bus = OpenCanBus(parsed.value(), open_gs_usb);
  if (!bus) return UriError(uri, bus.error().message);
  return bus;
}

}  // namespace hilrig::rig
