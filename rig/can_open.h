// One way to open a CAN bus from a command line: a URI names the backend and its arguments, so
// that every command reaches every backend alike.
//   emulated                         a lone node on an emulated bus of its own
//   udp:BASE_PORT[:INDEX[:COUNT]]    the loopback UDP bus (node 1 of 2 by default: the peer of a
//                                    runner, whose forwarder is node 0)
//   socketcan:IFACE                  a Linux SocketCAN interface (can0, vcan0)
//   gs_usb[:SERIAL]                  a gs_usb adapter over libusb (the first one, or the one with
//                                    that USB serial number)
// A URI that names no backend, or a backend with bad arguments, is an error naming the URI and
// what is wrong with it; a backend that cannot open says why.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "rig/can_bus.h"
#include "rig/gs_usb_transport.h"
#include "rig/result.h"
#include "rig/udp_bus.h"

namespace hilrig::rig {

struct CanBusUri {
  enum class Scheme { kEmulated, kUdp, kSocketCan, kGsUsb };
  Scheme scheme = Scheme::kEmulated;
  UdpBusConfig udp;        // kUdp
  std::string interface;   // kSocketCan
  std::string usb_serial;  // kGsUsb; empty: the first adapter found
};

Result<CanBusUri> ParseCanBusUri(const std::string& uri);

// Where a gs_usb adapter's transport comes from: libusb by default, a fake device in tests.
using GsUsbTransportOpener =
    std::function<Result<std::unique_ptr<GsUsbTransport>>(const std::string& usb_serial)>;

Result<std::unique_ptr<CanBus>> OpenCanBus(const CanBusUri& uri,
                                           const GsUsbTransportOpener& open_gs_usb = {});
// Parses, then opens; errors name the URI.
Result<std::unique_ptr<CanBus>> OpenCanBus(const std::string& uri,
                                           const GsUsbTransportOpener& open_gs_usb = {});

}  // namespace hilrig::rig
