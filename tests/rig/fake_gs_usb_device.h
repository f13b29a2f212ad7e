// FakeGsUsbDevice is an in-memory gs_usb adapter behind the GsUsbTransport seam, so GsUsbBus and
// the CanBus conformance suite run without USB. It answers the control requests the way
// candleLight firmware does (and records them, so tests can check the open sequence), echoes
// every host frame it is sent, stamped with its own 32-bit µs clock when hardware timestamps are
// on, and can be unplugged mid-run.
//
// Several fake devices share one FakeCanWire: a frame one started device sends reaches every
// other started device as an RX frame, like adapters on one physical bus. The wire owns the
// device clock (advanced by the test, never read from the OS) and can inject error frames, which
// every started device reports to its host as a controller would.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "rig/can_frame.h"
#include "rig/gs_usb_protocol.h"
#include "rig/gs_usb_transport.h"
#include "rig/result.h"

namespace hilrig::rig {

class FakeGsUsbDevice;

class FakeCanWire {
 public:
  // The device clock starts here; tests start it near 2^32 µs to cross the wrap early.
  explicit FakeCanWire(std::uint32_t start_time_us = 0) : start_time_us_(start_time_us) {}
  ~FakeCanWire();
  FakeCanWire(const FakeCanWire&) = delete;
  FakeCanWire& operator=(const FakeCanWire&) = delete;

  void AdvanceNs(std::int64_t dt_ns) { elapsed_ns_ += dt_ns; }
  std::uint32_t device_time_us() const;
  // Every started device reports `error_frame` to its host.
  void InjectErrorFrame(const CanFrame& error_frame);

 private:
  friend class FakeGsUsbDevice;
  void Attach(FakeGsUsbDevice* device) { devices_.push_back(device); }
  void Detach(FakeGsUsbDevice* device);
  void Deliver(const FakeGsUsbDevice* from, const CanFrame& frame);

  std::uint32_t start_time_us_;
  std::int64_t elapsed_ns_ = 0;
  std::vector<FakeGsUsbDevice*> devices_;
};

// A candleLight (STM32F072 bxCAN at 48 MHz, classic CAN, hardware timestamps).
GsUsbBtConst CandleLightBtConst();
// An STM32G4 FDCAN board at 170 MHz with CAN FD and BT_CONST_EXT.
GsUsbBtConst FdCanBtConst();

struct FakeGsUsbDeviceConfig {
  GsUsbDeviceConfig device_config{.icount = 0, .sw_version = 2, .hw_version = 1};
  GsUsbBtConst bt_const = CandleLightBtConst();
  // False models a bus where nobody acknowledges: frames are accepted but never echoed.
  bool echo = true;
};

struct RecordedControlRequest {
  bool device_to_host = false;
  std::uint8_t request = 0;
  std::uint16_t value = 0;
  std::uint16_t index = 0;
  std::vector<std::uint8_t> data;  // sent (OUT) or answered (IN)
};

class FakeGsUsbDevice final : public GsUsbTransport {
 public:
  explicit FakeGsUsbDevice(FakeCanWire& wire, FakeGsUsbDeviceConfig config = {});
  ~FakeGsUsbDevice() override;
  FakeGsUsbDevice(const FakeGsUsbDevice&) = delete;
  FakeGsUsbDevice& operator=(const FakeGsUsbDevice&) = delete;

  Result<void> ControlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index,
                          std::span<const std::uint8_t> data) override;
  Result<std::size_t> ControlIn(std::uint8_t request, std::uint16_t value, std::uint16_t index,
                                std::span<std::uint8_t> data) override;
  Result<void> BulkOut(std::span<const std::uint8_t> packet) override;
  Result<std::size_t> BulkIn(std::span<std::uint8_t> packet, int timeout_ms) override;
  bool unplugged() const override { return unplugged_; }

  // From now on every transfer fails as unplugged.
  void Unplug() { unplugged_ = true; }
  void set_echo(bool echo) { config_.echo = echo; }
  // A raw packet for the host, e.g. a malformed one.
  void QueuePacket(std::vector<std::uint8_t> packet) { to_host_.push_back(std::move(packet)); }
  // A frame arriving from the bus (stamped now if hardware timestamps are on).
  void ReceiveFromWire(const CanFrame& frame, bool overflow = false);

  const std::vector<RecordedControlRequest>& control_requests() const { return controls_; }
  const std::vector<GsUsbHostFrame>& frames_from_host() const { return from_host_; }
  bool started() const { return mode_.mode == kGsUsbModeStart; }
  const GsUsbMode& mode() const { return mode_; }
  std::optional<GsUsbBitTiming> bit_timing() const { return bit_timing_; }
  std::optional<GsUsbBitTiming> data_bit_timing() const { return data_bit_timing_; }
  std::size_t packets_waiting() const { return to_host_.size(); }

 private:
  Result<void> HandleOut(std::uint8_t request, std::span<const std::uint8_t> data);
  void QueueHostFrame(GsUsbHostFrame host_frame);

  FakeCanWire& wire_;
  FakeGsUsbDeviceConfig config_;
  bool unplugged_ = false;
  bool host_format_seen_ = false;
  GsUsbMode mode_{};
  std::optional<GsUsbBitTiming> bit_timing_;
  std::optional<GsUsbBitTiming> data_bit_timing_;
  std::vector<RecordedControlRequest> controls_;
  std::vector<GsUsbHostFrame> from_host_;
  std::deque<std::vector<std::uint8_t>> to_host_;
};

}  // namespace hilrig::rig
