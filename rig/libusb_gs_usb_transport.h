// LibusbGsUsbTransport is the real GsUsbTransport: a gs_usb adapter opened through libusb-1.0 from
// user space, found by the USB ids of the known gs_usb firmwares. It claims interface 0 (detaching
// the kernel's gs_usb driver if it holds it, and handing it back on close) and takes the bulk
// endpoints from the interface descriptor rather than assuming addresses, since firmwares differ.
//
// Bulk IN runs asynchronously: a few transfers stay submitted, and BulkIn with timeout 0 only
// lets libusb complete what has already arrived, so a poll never blocks the rig's loop. Control
// and bulk OUT transfers are synchronous with a bounded timeout. LIBUSB_ERROR_NO_DEVICE (or a
// transfer that completes with LIBUSB_TRANSFER_NO_DEVICE) makes the transport unplugged for good.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "rig/gs_usb_transport.h"
#include "rig/result.h"

namespace hilrig::rig {

struct UsbDeviceId {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
};

// candleLight / CANable (OpenMoko), the pid.codes candleLight id, the CES CANext FD, and the
// ABE CANdebugger FD: the ids Linux's gs_usb driver binds to.
inline constexpr std::array<UsbDeviceId, 4> kKnownGsUsbDevices = {
    UsbDeviceId{0x1d50, 0x606f}, UsbDeviceId{0x1209, 0x2323}, UsbDeviceId{0x1cd2, 0x606f},
    UsbDeviceId{0x16d0, 0x10b8}};

// The first attached device with one of `ids` and, unless `serial` is empty, that USB serial
// number. Fails with a message starting "no gs_usb device found" when there is none or libusb
// cannot enumerate at all (no /dev/bus/usb in a container).
Result<std::unique_ptr<GsUsbTransport>> OpenLibusbGsUsbTransport(
    std::span<const UsbDeviceId> ids = kKnownGsUsbDevices, const std::string& serial = "");

}  // namespace hilrig::rig
