#include "rig/libusb_gs_usb_transport.h"

#include <libusb.h>

#include <algorithm>
#include <array>
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace hilrig::rig {

namespace {

constexpr int kInterface = 0;
constexpr unsigned kControlTimeoutMs = 1000;
constexpr unsigned kBulkOutTimeoutMs = 1000;
constexpr std::size_t kInTransfers = 4;      // keep the pipe busy while the host is elsewhere
constexpr std::size_t kInPacketBytes = 512;  // a high-speed bulk packet; host frames are <= 80
// bmRequestType: direction | vendor | interface (the libusb enums do not mix in C++20).
constexpr std::uint8_t kVendorToInterface = 0x00 | 0x40 | 0x01;
constexpr std::uint8_t kVendorFromInterface = 0x80 | 0x40 | 0x01;
static_assert(LIBUSB_REQUEST_TYPE_VENDOR == 0x40 && LIBUSB_RECIPIENT_INTERFACE == 0x01);

std::string LibusbMessage(const char* what, int code) {
  return std::string("gs_usb ") + what + ": " + libusb_error_name(code);
}

bool Matches(const libusb_device_descriptor& descriptor, std::span<const UsbDeviceId> ids) {
  return std::any_of(ids.begin(), ids.end(), [&](const UsbDeviceId& id) {
    return id.vendor_id == descriptor.idVendor && id.product_id == descriptor.idProduct;
  });
}

struct BulkEndpoints {
  std::uint8_t in = 0;
  std::uint8_t out = 0;
};

Result<BulkEndpoints> FindBulkEndpoints(libusb_device* device) {
  libusb_config_descriptor* config = nullptr;
  if (int rc = libusb_get_active_config_descriptor(device, &config); rc != 0) {
    return MakeError(LibusbMessage("reading the configuration descriptor", rc));
  }
  BulkEndpoints endpoints;
  if (config->bNumInterfaces > kInterface && config->interface[kInterface].num_altsetting > 0) {
    const libusb_interface_descriptor& alt = config->interface[kInterface].altsetting[0];
    for (int i = 0; i < alt.bNumEndpoints; ++i) {
      const libusb_endpoint_descriptor& ep = alt.endpoint[i];
      if ((ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) != LIBUSB_TRANSFER_TYPE_BULK) continue;
      std::uint8_t& slot =
          (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) ? endpoints.in : endpoints.out;
      if (slot == 0) slot = ep.bEndpointAddress;
    }
  }
  libusb_free_config_descriptor(config);
  if (endpoints.in == 0 || endpoints.out == 0) {
    return MakeError("gs_usb: interface 0 has no bulk IN and OUT endpoint pair");
  }
  return endpoints;
}

class LibusbGsUsbTransport final : public GsUsbTransport {
 public:
  LibusbGsUsbTransport(libusb_context* context, libusb_device_handle* handle,
                       BulkEndpoints endpoints)
      : context_(context), handle_(handle), endpoints_(endpoints) {}

  ~LibusbGsUsbTransport() override {
    CancelInTransfers();
    libusb_release_interface(handle_, kInterface);
    libusb_close(handle_);
    libusb_exit(context_);
  }

  Result<void> StartInTransfers() {
    for (std::size_t i = 0; i < kInTransfers; ++i) {
      InTransfer& slot = in_transfers_[i];
      slot.transfer = libusb_alloc_transfer(0);
      if (slot.transfer == nullptr) return MakeError("gs_usb: cannot allocate a USB transfer");
      libusb_fill_bulk_transfer(slot.transfer, handle_, endpoints_.in, slot.buffer.data(),
                                static_cast<int>(slot.buffer.size()), &OnInComplete, this, 0);
      if (int rc = libusb_submit_transfer(slot.transfer); rc != 0) {
        return Fail("submitting bulk IN", rc);
      }
      slot.submitted = true;
    }
    return {};
  }

  Result<void> ControlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index,
                          std::span<const std::uint8_t> data) override {
    if (unplugged_) return MakeError(std::string(kGsUsbUnpluggedMessage));
    // libusb wants a mutable buffer even for OUT transfers.
    std::vector<std::uint8_t> buffer(data.begin(), data.end());
    const int rc =
        libusb_control_transfer(handle_, kVendorToInterface, request, value, index, buffer.data(),
                                static_cast<std::uint16_t>(buffer.size()), kControlTimeoutMs);
    if (rc < 0) return Fail("control OUT", rc);
    return {};
  }

  Result<std::size_t> ControlIn(std::uint8_t request, std::uint16_t value, std::uint16_t index,
                                std::span<std::uint8_t> data) override {
    if (unplugged_) return MakeError(std::string(kGsUsbUnpluggedMessage));
    const int rc =
        libusb_control_transfer(handle_, kVendorFromInterface, request, value, index, data.data(),
                                static_cast<std::uint16_t>(data.size()), kControlTimeoutMs);
    if (rc < 0) return Fail("control IN", rc);
    return static_cast<std::size_t>(rc);
  }

  Result<void> BulkOut(std::span<const std::uint8_t> packet) override {
    if (unplugged_) return MakeError(std::string(kGsUsbUnpluggedMessage));
    std::vector<std::uint8_t> buffer(packet.begin(), packet.end());
    int transferred = 0;
    const int rc =
        libusb_bulk_transfer(handle_, endpoints_.out, buffer.data(),
                             static_cast<int>(buffer.size()), &transferred, kBulkOutTimeoutMs);
    if (rc != 0) return Fail("bulk OUT", rc);
    if (static_cast<std::size_t>(transferred) != buffer.size()) {
      return MakeError("gs_usb bulk OUT: short write");
    }
    return {};
  }

  Result<std::size_t> BulkIn(std::span<std::uint8_t> packet, int timeout_ms) override {
    if (unplugged_) return MakeError(std::string(kGsUsbUnpluggedMessage));
    if (received_.empty()) {
      timeval timeout{timeout_ms / 1000, (timeout_ms % 1000) * 1000};
      if (int rc = libusb_handle_events_timeout_completed(context_, &timeout, nullptr); rc != 0) {
        return Fail("handling USB events", rc);
      }
    }
    if (unplugged_) return MakeError(std::string(kGsUsbUnpluggedMessage));
    if (!transfer_error_.empty()) return MakeError(std::exchange(transfer_error_, {}));
    if (received_.empty()) return std::size_t{0};
    const std::vector<std::uint8_t> front = std::move(received_.front());
    received_.pop_front();
    const std::size_t size = std::min(front.size(), packet.size());
    std::copy_n(front.begin(), size, packet.begin());
    return size;
  }

  bool unplugged() const override { return unplugged_; }

 private:
  struct InTransfer {
    libusb_transfer* transfer = nullptr;
    std::array<std::uint8_t, kInPacketBytes> buffer{};
    bool submitted = false;
  };

  static void LIBUSB_CALL OnInComplete(libusb_transfer* transfer) {
    static_cast<LibusbGsUsbTransport*>(transfer->user_data)->InComplete(transfer);
  }

  void InComplete(libusb_transfer* transfer) {
    InTransfer& slot = SlotOf(transfer);
    slot.submitted = false;
    switch (transfer->status) {
      case LIBUSB_TRANSFER_COMPLETED:
        received_.emplace_back(transfer->buffer, transfer->buffer + transfer->actual_length);
        break;
      case LIBUSB_TRANSFER_NO_DEVICE:
        unplugged_ = true;
        return;
      case LIBUSB_TRANSFER_CANCELLED:
        return;
      default:
        transfer_error_ = "gs_usb bulk IN transfer failed with status " +
                          std::to_string(static_cast<int>(transfer->status));
        break;
    }
    if (int rc = libusb_submit_transfer(transfer); rc == 0) {
      slot.submitted = true;
    } else if (rc == LIBUSB_ERROR_NO_DEVICE) {
      unplugged_ = true;
    } else {
      transfer_error_ = LibusbMessage("resubmitting bulk IN", rc);
    }
  }

  InTransfer& SlotOf(libusb_transfer* transfer) {
    for (InTransfer& slot : in_transfers_) {
      if (slot.transfer == transfer) return slot;
    }
    HILRIG_CHECK(false, "a bulk IN completion for a transfer this transport does not own");
    return in_transfers_[0];
  }

  // Cancelled transfers still complete through the callback, so wait for them before freeing.
  void CancelInTransfers() {
    for (InTransfer& slot : in_transfers_) {
      if (slot.submitted) libusb_cancel_transfer(slot.transfer);
    }
    for (int round = 0; round < 100 && AnySubmitted(); ++round) {
      timeval timeout{0, 10'000};
      libusb_handle_events_timeout_completed(context_, &timeout, nullptr);
    }
    for (InTransfer& slot : in_transfers_) {
      if (slot.transfer != nullptr && !slot.submitted) libusb_free_transfer(slot.transfer);
    }
  }

  bool AnySubmitted() const {
    return std::any_of(in_transfers_.begin(), in_transfers_.end(),
                       [](const InTransfer& slot) { return slot.submitted; });
  }

  Error Fail(const char* what, int code) {
    if (code == LIBUSB_ERROR_NO_DEVICE) {
      unplugged_ = true;
      return MakeError(std::string(kGsUsbUnpluggedMessage));
    }
    return MakeError(LibusbMessage(what, code));
  }

  libusb_context* context_;
  libusb_device_handle* handle_;
  BulkEndpoints endpoints_;
  std::array<InTransfer, kInTransfers> in_transfers_{};
  std::deque<std::vector<std::uint8_t>> received_;
  std::string transfer_error_;
  bool unplugged_ = false;
};

// Whether an opened device reports `serial` as its serial number string.
bool HasSerial(libusb_device_handle* handle, const libusb_device_descriptor& descriptor,
               const std::string& serial) {
  unsigned char text[256] = {};
  const int length =
      libusb_get_string_descriptor_ascii(handle, descriptor.iSerialNumber, text, sizeof(text));
  return length >= 0 && serial == std::string(reinterpret_cast<const char*>(text),
                                              static_cast<std::size_t>(length));
}

// The first matching device (with `serial`, unless empty), opened.
Result<libusb_device_handle*> OpenFirstMatching(libusb_context* context,
                                                std::span<const UsbDeviceId> ids,
                                                const std::string& serial) {
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context, &list);
  if (count < 0) {
    return MakeError(std::string("no gs_usb device found (listing devices: ") +
                     libusb_error_name(static_cast<int>(count)) + ")");
  }
  libusb_device_handle* handle = nullptr;
  std::string last_error;
  for (ssize_t i = 0; i < count && handle == nullptr; ++i) {
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(list[i], &descriptor) != 0) continue;
    if (!Matches(descriptor, ids)) continue;
    if (int rc = libusb_open(list[i], &handle); rc != 0) {
      last_error = LibusbMessage("opening a matching device", rc);
      handle = nullptr;
    } else if (!serial.empty() && !HasSerial(handle, descriptor, serial)) {
      libusb_close(handle);
      handle = nullptr;
    }
  }
  libusb_free_device_list(list, 1);
  if (handle == nullptr) {
    const std::string wanted = serial.empty() ? "" : " with serial " + serial;
    return MakeError(last_error.empty()
                         ? "no gs_usb device found" + wanted
                         : "no gs_usb device found that could be opened: " + last_error);
  }
  return handle;
}

}  // namespace

Result<std::unique_ptr<GsUsbTransport>> OpenLibusbGsUsbTransport(std::span<const UsbDeviceId> ids,
                                                                 const std::string& serial) {
  libusb_context* context = nullptr;
  if (int rc = libusb_init(&context); rc != 0) {
    return MakeError(std::string("no gs_usb device found (libusb_init: ") + libusb_error_name(rc) +
                     ")");
  }
  Result<libusb_device_handle*> handle = OpenFirstMatching(context, ids, serial);
  if (!handle) {
    libusb_exit(context);
    return handle.error();
  }
  libusb_device_handle* device = handle.value();
  // Lets a bench machine keep the kernel's gs_usb driver loaded; libusb re-attaches on release.
  libusb_set_auto_detach_kernel_driver(device, 1);
  Result<BulkEndpoints> endpoints = FindBulkEndpoints(libusb_get_device(device));
  int rc = endpoints ? libusb_claim_interface(device, kInterface) : 0;
  if (!endpoints || rc != 0) {
    libusb_close(device);
    libusb_exit(context);
    if (!endpoints) return endpoints.error();
    return MakeError(LibusbMessage("claiming interface 0", rc));
  }
  auto transport = std::make_unique<LibusbGsUsbTransport>(context, device, endpoints.value());
  if (Result<void> started = transport->StartInTransfers(); !started) return started.error();
  return std::unique_ptr<GsUsbTransport>(std::move(transport));
}

}  // namespace hilrig::rig
