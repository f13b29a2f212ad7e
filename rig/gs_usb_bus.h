// GsUsbBus puts a gs_usb adapter (candleLight, CANable and friends) behind the CanBus seam by
// speaking the gs_usb protocol from user space, over a GsUsbTransport (libusb on a bench, a fake
// device in tests). It is the path for machines whose kernel has no gs_usb driver or no SocketCAN
// at all, and it exposes what the kernel driver hides: the device's own timestamps and the echo
// that confirms each transmission.
//
// - Open: host format, device config (the channel must exist), BT_CONST (and BT_CONST_EXT for
//   FD), a mode reset so a device left running by a crashed process starts clean, bit timing
//   (and data bit timing), then mode start with the requested flags. Hardware timestamps are
//   requested whenever the device offers them.
// - Send: the frame goes out as a host frame with an echo_id naming a slot in a bounded in-flight
//   table; the device echoes it once it is on the wire, which frees the slot. A full table means
//   the device is not keeping up (or the bus is down): Send first collects the echoes already
//   waiting in the IN pipe (holding any RX frames for the next Receive), and only then fails
//   rather than queue without bound. frames_sent counts frames handed to the device.
// - Receive: drains the bulk IN pipe without waiting. RX frames pass the software filters (the
//   protocol has no hardware filters) and echoes come back marked tx_echo when own frames are
//   requested. Error frames from the device update state() and the error counters and are
//   delivered per the error-class mask.
// - Time: with hardware timestamps each frame carries the device's 32-bit µs clock, unwrapped to
//   64-bit ns and shifted onto the caller's time base at the first timestamped frame (so the
//   stamps keep the device's spacing and never decrease); without them frames get the now_ns of
//   the Receive that found them.
// - Unplug: the bus goes bus-off, unplugged() turns true, Send fails saying so, Receive returns
//   nothing. Nothing crashes and nothing retries; reopen when the device is back.
// - Close (and the destructor): mode reset, so the adapter leaves the bus.
//
// Threading: one thread per bus, like every CanBus.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rig/can_bus.h"
#include "rig/gs_usb_protocol.h"
#include "rig/gs_usb_transport.h"
#include "rig/result.h"

namespace hilrig::rig {

struct GsUsbOptions {
  std::int64_t bitrate_bps = 1'000'000;
  // 0: classic CAN only. Otherwise the FD data-phase bitrate; the device must support FD.
  std::int64_t data_bitrate_bps = 0;
  std::uint16_t channel = 0;
  bool listen_only = false;
  bool loopback = false;  // the controller's internal loopback: frames never reach the wire
  // Frames sent but not yet echoed; Linux's driver allows 10.
  std::size_t max_in_flight = 10;
  // Packets read per Receive at most, so one call cannot spin forever on a flooded bus.
  std::size_t max_packets_per_receive = 1024;
};

class GsUsbBus final : public CanBus {
 public:
  // Runs the open sequence over `transport`; fails with the step that went wrong.
  static Result<std::unique_ptr<GsUsbBus>> Open(std::unique_ptr<GsUsbTransport> transport,
                                                const GsUsbOptions& options);
  ~GsUsbBus() override;
  GsUsbBus(const GsUsbBus&) = delete;
  GsUsbBus& operator=(const GsUsbBus&) = delete;

  // Stops the channel (mode reset). Idempotent; a device already unplugged is not an error.
  Result<void> Close();

  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override;
  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override;
  void SetFilters(std::span<const CanFilter> filters) override;
  void SetReceiveErrorFrames(bool enabled) override;
  void SetErrorFrameMask(std::uint32_t class_mask) override;
  Result<void> SetReceiveOwnFrames(bool enabled) override;
  BusState state() const override { return state_; }
  BusCounters counters() const override { return counters_; }

  bool unplugged() const { return unplugged_; }
  const GsUsbDeviceConfig& device_config() const { return device_config_; }
  const GsUsbBtConst& bt_const() const { return bt_const_; }
  const GsUsbBitTiming& bit_timing() const { return bit_timing_; }
  std::optional<GsUsbBitTiming> data_bit_timing() const { return data_bit_timing_; }
  bool hardware_timestamps() const { return hardware_timestamps_; }
  std::size_t frames_in_flight() const;

 private:
  GsUsbBus(std::unique_ptr<GsUsbTransport> transport, const GsUsbOptions& options);

  Result<void> RunOpenSequence();
  Result<void> ReadDeviceLimits();
  Result<void> WriteBitTimings();
  Result<void> StartChannel();
  Result<void> Control(std::uint8_t request, std::span<const std::uint8_t> data, const char* step);
  Result<void> FailSend(Error error);
  // Marks the device gone if the transport says so; returns whether it did.
  bool NoteUnplug();
  std::vector<std::optional<CanFrame>>::iterator FindFreeSlot();
  // Reads what the IN pipe holds now, without waiting.
  void DrainPipe(std::int64_t now_ns, std::vector<TimedCanFrame>& out);
  void HandlePacket(std::span<const std::uint8_t> packet, std::int64_t now_ns,
                    std::vector<TimedCanFrame>& out);
  void HandleEcho(const GsUsbHostFrame& host_frame, std::int64_t time_ns,
                  std::vector<TimedCanFrame>& out);
  void HandleErrorFrame(const CanFrame& frame, std::int64_t time_ns,
                        std::vector<TimedCanFrame>& out);
  // Forgets every frame waiting for its echo, counting each as dropped before transmission.
  void DropInFlight();
  std::int64_t FrameTimeNs(const GsUsbHostFrame& host_frame, std::int64_t now_ns);

  std::unique_ptr<GsUsbTransport> transport_;
  GsUsbOptions options_;
  GsUsbDeviceConfig device_config_{};
  GsUsbBtConst bt_const_{};
  GsUsbBitTiming bit_timing_{};
  std::optional<GsUsbBitTiming> data_bit_timing_;
  bool hardware_timestamps_ = false;
  bool started_ = false;
  bool unplugged_ = false;

  std::vector<std::optional<CanFrame>> in_flight_;  // indexed by echo_id
  // Frames read while Send looked for echoes, handed out by the next Receive.
  std::vector<TimedCanFrame> held_;
  std::vector<CanFilter> filters_;
  std::uint32_t error_mask_ = 0;
  bool receive_own_frames_ = false;
  BusState state_ = BusState::kErrorActive;
  BusCounters counters_{};

  GsUsbTimestampUnwrapper unwrapper_{};
  std::optional<std::int64_t> device_to_host_offset_ns_;
  std::int64_t last_time_ns_ = 0;
};

// Opens the first gs_usb adapter libusb finds (see kKnownGsUsbDevices) and starts it with
// `options`. Fails with a message starting "no gs_usb device found" when none is attached or USB
// cannot be reached at all.
Result<std::unique_ptr<CanBus>> OpenGsUsb(const GsUsbOptions& options);

}  // namespace hilrig::rig
