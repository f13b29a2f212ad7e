// GsUsbTransport is the USB side of a gs_usb adapter reduced to the four transfers the protocol
// uses: vendor control requests out and in (on the adapter's interface), and one bulk pipe each
// way for host frames. GsUsbBus speaks the protocol over this seam, so it runs unchanged over
// libusb (rig/libusb_gs_usb_transport.h) and over the in-memory fake device the tests use.
//
// Errors are values. Unplugging is the one error the bus must treat differently from a failed
// transfer (it is final: the bus goes bus-off and stops talking to the device), so a transport
// that sees the device vanish fails that call and every later one and reports unplugged().
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "rig/result.h"

namespace hilrig::rig {

// Message of the error a transport returns once the device is gone.
inline constexpr std::string_view kGsUsbUnpluggedMessage = "gs_usb device unplugged";

class GsUsbTransport {
 public:
  virtual ~GsUsbTransport() = default;

  // A vendor request to the interface (bmRequestType 0x41) carrying `data`.
  virtual Result<void> ControlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index,
                                  std::span<const std::uint8_t> data) = 0;
  // A vendor request from the interface (bmRequestType 0xC1); returns the bytes received.
  virtual Result<std::size_t> ControlIn(std::uint8_t request, std::uint16_t value,
                                        std::uint16_t index, std::span<std::uint8_t> data) = 0;
  // One host frame to the bulk OUT endpoint.
  virtual Result<void> BulkOut(std::span<const std::uint8_t> packet) = 0;
  // One packet from the bulk IN endpoint into `packet`; returns its size, or 0 if none arrived
  // within timeout_ms. timeout_ms == 0 polls: it never waits.
  virtual Result<std::size_t> BulkIn(std::span<std::uint8_t> packet, int timeout_ms) = 0;
  // True once the device has gone away; from then on every call fails.
  virtual bool unplugged() const = 0;
};

}  // namespace hilrig::rig
