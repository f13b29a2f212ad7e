#include "tests/rig/fake_gs_usb_device.h"

#include <algorithm>
#include <string>
#include <utility>

namespace hilrig::rig {

namespace {

constexpr std::uint16_t kInterfaceIndex = 0;

Error Unplugged() { return MakeError(std::string(kGsUsbUnpluggedMessage)); }
// A request the firmware does not know makes it stall the control pipe.
Error Stall(std::uint8_t request) {
  return MakeError("fake gs_usb: control request " + std::to_string(request) + " stalled");
}

}  // namespace

FakeCanWire::~FakeCanWire() {
  HILRIG_CHECK(devices_.empty(), "fake devices must not outlive their wire");
}

std::uint32_t FakeCanWire::device_time_us() const {
  // Modular on purpose: the device counter is 32 bits and wraps.
  return static_cast<std::uint32_t>(start_time_us_ +
                                    static_cast<std::uint64_t>(elapsed_ns_ / 1000));
}

void FakeCanWire::InjectErrorFrame(const CanFrame& error_frame) {
  for (FakeGsUsbDevice* device : devices_) {
    if (device->started()) device->ReceiveFromWire(error_frame);
  }
}

void FakeCanWire::Detach(FakeGsUsbDevice* device) {
  devices_.erase(std::remove(devices_.begin(), devices_.end(), device), devices_.end());
}

void FakeCanWire::Deliver(const FakeGsUsbDevice* from, const CanFrame& frame) {
  for (FakeGsUsbDevice* device : devices_) {
    if (device != from && device->started()) device->ReceiveFromWire(frame);
  }
}

GsUsbBtConst CandleLightBtConst() {
  GsUsbBtConst bt_const;
  bt_const.features = gs_usb_feature::kListenOnly | gs_usb_feature::kLoopBack |
                      gs_usb_feature::kHwTimestamp | gs_usb_feature::kIdentify;
  bt_const.fclk_can_hz = 48'000'000;
  bt_const.nominal = GsUsbTimingLimits{.tseg1_min = 1,
                                       .tseg1_max = 16,
                                       .tseg2_min = 1,
                                       .tseg2_max = 8,
                                       .sjw_max = 4,
                                       .brp_min = 1,
                                       .brp_max = 1024,
                                       .brp_inc = 1};
  return bt_const;
}

GsUsbBtConst FdCanBtConst() {
  GsUsbBtConst bt_const;
  bt_const.features = gs_usb_feature::kListenOnly | gs_usb_feature::kLoopBack |
                      gs_usb_feature::kHwTimestamp | gs_usb_feature::kFd |
                      gs_usb_feature::kBtConstExt;
  bt_const.fclk_can_hz = 170'000'000;
  bt_const.nominal = GsUsbTimingLimits{.tseg1_min = 1,
                                       .tseg1_max = 256,
                                       .tseg2_min = 1,
                                       .tseg2_max = 128,
                                       .sjw_max = 128,
                                       .brp_min = 1,
                                       .brp_max = 512,
                                       .brp_inc = 1};
  bt_const.data = GsUsbTimingLimits{.tseg1_min = 1,
                                    .tseg1_max = 32,
                                    .tseg2_min = 1,
                                    .tseg2_max = 16,
                                    .sjw_max = 16,
                                    .brp_min = 1,
                                    .brp_max = 32,
                                    .brp_inc = 1};
  return bt_const;
}

FakeGsUsbDevice::FakeGsUsbDevice(FakeCanWire& wire, FakeGsUsbDeviceConfig config)
    : wire_(wire), config_(std::move(config)) {
  wire_.Attach(this);
}

FakeGsUsbDevice::~FakeGsUsbDevice() { wire_.Detach(this); }

Result<void> FakeGsUsbDevice::ControlOut(std::uint8_t request, std::uint16_t value,
                                         std::uint16_t index, std::span<const std::uint8_t> data) {
  if (unplugged_) return Unplugged();
  controls_.push_back({false, request, value, index, {data.begin(), data.end()}});
  if (index != kInterfaceIndex) return Stall(request);
  return HandleOut(request, data);
}

Result<void> FakeGsUsbDevice::HandleOut(std::uint8_t request, std::span<const std::uint8_t> data) {
  switch (request) {
    case gs_usb_request::kHostFormat:
      host_format_seen_ = true;
      return {};
    case gs_usb_request::kBitTiming:
    case gs_usb_request::kDataBitTiming: {
      Result<GsUsbBitTiming> timing = DecodeGsUsbBitTiming(data);
      if (!timing) return Stall(request);
      (request == gs_usb_request::kBitTiming ? bit_timing_ : data_bit_timing_) = timing.value();
      return {};
    }
    case gs_usb_request::kMode: {
      Result<GsUsbMode> mode = DecodeGsUsbMode(data);
      // Firmware refuses to start a channel whose bit timing was never set.
      if (!mode || (mode.value().mode == kGsUsbModeStart && !bit_timing_)) return Stall(request);
      mode_ = mode.value();
      if (mode_.mode == kGsUsbModeReset) to_host_.clear();
      return {};
    }
    default:
      return Stall(request);
  }
}

Result<std::size_t> FakeGsUsbDevice::ControlIn(std::uint8_t request, std::uint16_t value,
                                               std::uint16_t index, std::span<std::uint8_t> data) {
  if (unplugged_) return Unplugged();
  std::vector<std::uint8_t> answer;
  if (request == gs_usb_request::kDeviceConfig) {
    const auto bytes = EncodeGsUsbDeviceConfig(config_.device_config);
    answer.assign(bytes.begin(), bytes.end());
  } else if (request == gs_usb_request::kBtConst) {
    const auto bytes = EncodeGsUsbBtConst(config_.bt_const);
    answer.assign(bytes.begin(), bytes.end());
  } else if (request == gs_usb_request::kBtConstExt && config_.bt_const.data) {
    const auto bytes = EncodeGsUsbBtConstExt(config_.bt_const);
    answer.assign(bytes.begin(), bytes.end());
  }
  controls_.push_back({true, request, value, index, answer});
  if (answer.empty() || index != kInterfaceIndex) return Stall(request);
  const std::size_t size = std::min(answer.size(), data.size());
  std::copy_n(answer.begin(), size, data.begin());
  return size;
}

Result<void> FakeGsUsbDevice::BulkOut(std::span<const std::uint8_t> packet) {
  if (unplugged_) return Unplugged();
  // Hosts send without the timestamp field; the device adds it to the echo.
  Result<GsUsbHostFrame> host_frame = DecodeGsUsbHostFrame(packet, /*timestamps_on=*/false);
  if (!host_frame) return MakeError("fake gs_usb: bad host frame: " + host_frame.error().message);
  if (!started()) return MakeError("fake gs_usb: frame for a channel that is not started");
  from_host_.push_back(host_frame.value());
  if (!config_.echo) return {};
  if ((mode_.flags & gs_usb_feature::kLoopBack) == 0) wire_.Deliver(this, host_frame.value().frame);
  QueueHostFrame(host_frame.value());
  return {};
}

Result<std::size_t> FakeGsUsbDevice::BulkIn(std::span<std::uint8_t> packet, int /*timeout_ms*/) {
  if (unplugged_) return Unplugged();
  if (to_host_.empty()) return std::size_t{0};
  const std::vector<std::uint8_t> front = std::move(to_host_.front());
  to_host_.pop_front();
  const std::size_t size = std::min(front.size(), packet.size());
  std::copy_n(front.begin(), size, packet.begin());
  return size;
}

void FakeGsUsbDevice::ReceiveFromWire(const CanFrame& frame, bool overflow) {
  GsUsbHostFrame host_frame;
  host_frame.frame = frame;
  host_frame.overflow = overflow;
  QueueHostFrame(std::move(host_frame));
}

void FakeGsUsbDevice::QueueHostFrame(GsUsbHostFrame host_frame) {
  host_frame.timestamp_us.reset();
  if (mode_.flags & gs_usb_feature::kHwTimestamp) host_frame.timestamp_us = wire_.device_time_us();
  to_host_.push_back(EncodeGsUsbHostFrame(host_frame));
}

}  // namespace hilrig::rig
