#include "rig/gs_usb_bus.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "rig/libusb_gs_usb_transport.h"

namespace hilrig::rig {

namespace {

constexpr std::uint16_t kInterfaceIndex = 0;

Error StepError(const char* step, const Error& error) {
  return MakeError(std::string("gs_usb open: ") + step + ": " + error.message);
}

}  // namespace

GsUsbBus::GsUsbBus(std::unique_ptr<GsUsbTransport> transport, const GsUsbOptions& options)
    : transport_(std::move(transport)), options_(options), in_flight_(options.max_in_flight) {}

GsUsbBus::~GsUsbBus() { (void)Close(); }

Result<std::unique_ptr<GsUsbBus>> GsUsbBus::Open(std::unique_ptr<GsUsbTransport> transport,
                                                 const GsUsbOptions& options) {
  HILRIG_CHECK(transport != nullptr, "GsUsbBus needs a transport");
  if (options.max_in_flight == 0 || options.max_in_flight >= kGsUsbEchoIdRx) {
    return MakeError("gs_usb open: max_in_flight must be between 1 and 2^32 - 2");
  }
  std::unique_ptr<GsUsbBus> bus(new GsUsbBus(std::move(transport), options));
  if (Result<void> opened = bus->RunOpenSequence(); !opened) return opened.error();
  return bus;
}

Result<void> GsUsbBus::RunOpenSequence() {
  // Old firmware byte-swaps unless told the host's order; newer firmware ignores it.
  if (Result<void> r = transport_->ControlOut(gs_usb_request::kHostFormat, kGsUsbHostFormatValue,
                                              kInterfaceIndex, EncodeGsUsbHostFormat());
      !r) {
    return StepError("host format", r.error());
  }
  std::array<std::uint8_t, kGsUsbDeviceConfigBytes> config_bytes{};
  Result<std::size_t> got =
      transport_->ControlIn(gs_usb_request::kDeviceConfig, 1, kInterfaceIndex, config_bytes);
  if (!got) return StepError("device config", got.error());
  Result<GsUsbDeviceConfig> config =
      DecodeGsUsbDeviceConfig(std::span(config_bytes).first(got.value()));
  if (!config) return StepError("device config", config.error());
  device_config_ = config.value();
  if (options_.channel >= device_config_.channel_count()) {
    return MakeError("gs_usb open: channel " + std::to_string(options_.channel) +
                     " requested, the device has " +
                     std::to_string(device_config_.channel_count()));
  }
  if (Result<void> r = ReadDeviceLimits(); !r) return r;
  if (Result<void> r =
          Control(gs_usb_request::kMode, EncodeGsUsbMode({kGsUsbModeReset, 0}), "mode reset");
      !r) {
    return r;
  }
  if (Result<void> r = WriteBitTimings(); !r) return r;
  return StartChannel();
}

Result<void> GsUsbBus::ReadDeviceLimits() {
  const bool want_fd = options_.data_bitrate_bps > 0;
  std::array<std::uint8_t, kGsUsbBtConstBytes> bytes{};
  Result<std::size_t> got =
      transport_->ControlIn(gs_usb_request::kBtConst, options_.channel, kInterfaceIndex, bytes);
  if (!got) return StepError("BT_CONST", got.error());
  Result<GsUsbBtConst> bt_const = DecodeGsUsbBtConst(std::span(bytes).first(got.value()));
  if (!bt_const) return StepError("BT_CONST", bt_const.error());
  bt_const_ = bt_const.value();
  if (!want_fd) return {};
  constexpr std::uint32_t kFdFeatures = gs_usb_feature::kFd | gs_usb_feature::kBtConstExt;
  if ((bt_const_.features & kFdFeatures) != kFdFeatures) {
    return MakeError("gs_usb open: a data bitrate was requested but the device has no CAN FD");
  }
  std::array<std::uint8_t, kGsUsbBtConstExtBytes> ext_bytes{};
  got = transport_->ControlIn(gs_usb_request::kBtConstExt, options_.channel, kInterfaceIndex,
                              ext_bytes);
  if (!got) return StepError("BT_CONST_EXT", got.error());
  Result<GsUsbBtConst> ext = DecodeGsUsbBtConstExt(std::span(ext_bytes).first(got.value()));
  if (!ext) return StepError("BT_CONST_EXT", ext.error());
  bt_const_ = ext.value();
  return {};
}

Result<void> GsUsbBus::WriteBitTimings() {
  Result<GsUsbBitTiming> nominal =
      CalculateGsUsbBitTiming(options_.bitrate_bps, bt_const_.fclk_can_hz, bt_const_.nominal);
  if (!nominal) return StepError("bit timing", nominal.error());
  bit_timing_ = nominal.value();
  if (Result<void> r =
          Control(gs_usb_request::kBitTiming, EncodeGsUsbBitTiming(bit_timing_), "bit timing");
      !r) {
    return r;
  }
  if (options_.data_bitrate_bps <= 0) return {};
  // The data phase samples later than 87.5 % would leave too little of a short bit after it.
  Result<GsUsbBitTiming> data = CalculateGsUsbBitTiming(
      options_.data_bitrate_bps, bt_const_.fclk_can_hz, *bt_const_.data, /*sample_point=*/0.75);
  if (!data) return StepError("data bit timing", data.error());
  data_bit_timing_ = data.value();
  return Control(gs_usb_request::kDataBitTiming, EncodeGsUsbBitTiming(*data_bit_timing_),
                 "data bit timing");
}

Result<void> GsUsbBus::StartChannel() {
  std::uint32_t flags = 0;
  const auto require = [&](bool wanted, std::uint32_t feature, const char* name) -> Result<void> {
    if (!wanted) return {};
    if ((bt_const_.features & feature) == 0) {
      return MakeError(std::string("gs_usb open: the device cannot do ") + name);
    }
    flags |= feature;
    return {};
  };
  if (Result<void> r = require(options_.listen_only, gs_usb_feature::kListenOnly, "listen-only");
      !r) {
    return r;
  }
  if (Result<void> r = require(options_.loopback, gs_usb_feature::kLoopBack, "loopback"); !r) {
    return r;
  }
  if (options_.data_bitrate_bps > 0) flags |= gs_usb_feature::kFd;
  hardware_timestamps_ = (bt_const_.features & gs_usb_feature::kHwTimestamp) != 0;
  if (hardware_timestamps_) flags |= gs_usb_feature::kHwTimestamp;
  if (Result<void> r =
          Control(gs_usb_request::kMode, EncodeGsUsbMode({kGsUsbModeStart, flags}), "mode start");
      !r) {
    return r;
  }
  started_ = true;
  return {};
}

Result<void> GsUsbBus::Control(std::uint8_t request, std::span<const std::uint8_t> data,
                               const char* step) {
  if (Result<void> r = transport_->ControlOut(request, options_.channel, kInterfaceIndex, data);
      !r) {
    NoteUnplug();
    return StepError(step, r.error());
  }
  return {};
}

Result<void> GsUsbBus::Close() {
  if (!started_ || unplugged_) return {};
  started_ = false;
  if (Result<void> r =
          transport_->ControlOut(gs_usb_request::kMode, options_.channel, kInterfaceIndex,
                                 EncodeGsUsbMode({kGsUsbModeReset, 0}));
      !r) {
    if (NoteUnplug()) return {};
    return MakeError("gs_usb close: mode reset: " + r.error().message);
  }
  return {};
}

std::size_t GsUsbBus::frames_in_flight() const {
  return static_cast<std::size_t>(std::count_if(in_flight_.begin(), in_flight_.end(),
                                                [](const auto& s) { return s.has_value(); }));
}

bool GsUsbBus::NoteUnplug() {
  if (!transport_->unplugged()) return false;
  if (!unplugged_) {
    unplugged_ = true;
    state_ = BusState::kBusOff;
    // Frames the device never confirmed will not be confirmed now.
    DropInFlight();
  }
  return true;
}

void GsUsbBus::DropInFlight() {
  for (std::optional<CanFrame>& slot : in_flight_) {
    if (slot) ++counters_.frames_dropped_tx;
    slot.reset();
  }
}

Result<void> GsUsbBus::FailSend(Error error) {
  ++counters_.send_failures;
  return error;
}

Result<void> GsUsbBus::Send(const CanFrame& frame, std::int64_t now_ns) {
  if (unplugged_) return FailSend(MakeError(std::string(kGsUsbUnpluggedMessage)));
  if (!started_) return FailSend(MakeError("gs_usb send: the channel is closed"));
  if (Result<void> valid = ValidateFrame(frame); !valid) {
    return FailSend(MakeError("gs_usb send: " + valid.error().message));
  }
  if (frame.error) return FailSend(MakeError("gs_usb send: an adapter cannot send error frames"));
  if (frame.fd && !data_bit_timing_) {
    return FailSend(MakeError("gs_usb send: CAN FD frame on a channel opened without FD"));
  }
  if (state_ == BusState::kBusOff) return FailSend(MakeError("gs_usb send: the bus is off"));
  auto free_slot = FindFreeSlot();
  if (free_slot == in_flight_.end()) {
    // The echoes that would free a slot may already be waiting in the IN pipe: collect them
    // (and whatever arrived with them, kept for the next Receive) before giving up.
    DrainPipe(now_ns, held_);
    free_slot = FindFreeSlot();
  }
  if (free_slot == in_flight_.end()) {
    return FailSend(MakeError("gs_usb send: " + std::to_string(in_flight_.size()) +
                              " frames are waiting for their echo; the device is not keeping up"));
  }
  GsUsbHostFrame host_frame;
  host_frame.echo_id = static_cast<std::uint32_t>(free_slot - in_flight_.begin());
  host_frame.frame = frame;
  host_frame.channel = static_cast<std::uint8_t>(options_.channel);
  if (Result<void> sent = transport_->BulkOut(EncodeGsUsbHostFrame(host_frame)); !sent) {
    NoteUnplug();
    return FailSend(MakeError("gs_usb send: " + sent.error().message));
  }
  *free_slot = frame;
  ++counters_.frames_sent;
  return {};
}

std::vector<std::optional<CanFrame>>::iterator GsUsbBus::FindFreeSlot() {
  return std::find_if(in_flight_.begin(), in_flight_.end(),
                      [](const auto& slot) { return !slot.has_value(); });
}

std::size_t GsUsbBus::Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) {
  const std::size_t before = out.size();
  out.insert(out.end(), held_.begin(), held_.end());
  held_.clear();
  DrainPipe(now_ns, out);
  return out.size() - before;
}

void GsUsbBus::DrainPipe(std::int64_t now_ns, std::vector<TimedCanFrame>& out) {
  std::array<std::uint8_t, kGsUsbMaxHostFrameBytes> packet{};
  for (std::size_t k = 0; k < options_.max_packets_per_receive && !unplugged_ && started_; ++k) {
    Result<std::size_t> got = transport_->BulkIn(packet, /*timeout_ms=*/0);
    if (!got) {
      NoteUnplug();
      return;  // a failed transfer has no frame to give; the next call tries again
    }
    if (got.value() == 0) return;
    HandlePacket(std::span(packet).first(got.value()), now_ns, out);
  }
}

void GsUsbBus::HandlePacket(std::span<const std::uint8_t> packet, std::int64_t now_ns,
                            std::vector<TimedCanFrame>& out) {
  Result<GsUsbHostFrame> decoded = DecodeGsUsbHostFrame(packet, hardware_timestamps_);
  if (!decoded) {
    ++counters_.frames_dropped_malformed;
    return;
  }
  const GsUsbHostFrame& host_frame = decoded.value();
  if (host_frame.channel != options_.channel) return;  // another channel's traffic
  const std::int64_t time_ns = FrameTimeNs(host_frame, now_ns);
  if (host_frame.is_tx_echo()) {
    HandleEcho(host_frame, time_ns, out);
    return;
  }
  if (host_frame.overflow) ++counters_.frames_dropped_rx_overflow;
  if (host_frame.frame.error) {
    HandleErrorFrame(host_frame.frame, time_ns, out);
    return;
  }
  if (!FilterAccepts(filters_, host_frame.frame)) return;
  out.push_back(TimedCanFrame{host_frame.frame, time_ns, /*tx_echo=*/false});
  ++counters_.frames_received;
}

void GsUsbBus::HandleEcho(const GsUsbHostFrame& host_frame, std::int64_t time_ns,
                          std::vector<TimedCanFrame>& out) {
  if (host_frame.echo_id >= in_flight_.size() || !in_flight_[host_frame.echo_id]) {
    ++counters_.frames_dropped_malformed;  // an echo for nothing we sent
    return;
  }
  // The frame as we sent it: some firmware does not echo the payload back faithfully.
  const CanFrame sent = *in_flight_[host_frame.echo_id];
  in_flight_[host_frame.echo_id].reset();
  if (!receive_own_frames_) return;
  out.push_back(TimedCanFrame{sent, time_ns, /*tx_echo=*/true});
}

void GsUsbBus::HandleErrorFrame(const CanFrame& frame, std::int64_t time_ns,
                                std::vector<TimedCanFrame>& out) {
  const std::vector<BusEvent> events = DecodeErrorFrame(frame, time_ns);
  if (const std::optional<BusState> announced = AnnouncedBusState(events)) state_ = *announced;
  for (const BusEvent& event : events) {
    if (event.kind == BusEventKind::kRxOverflow) ++counters_.frames_dropped_rx_overflow;
  }
  if (state_ == BusState::kBusOff) {
    // The controller discards its TX queue on bus-off, so those echoes will never come.
    DropInFlight();
  }
  // A counters-only frame yields no event, so the counters are read from the frame itself.
  if (frame.id & can_error::kCounters) {
    counters_.transmit_error_count = frame.data[6];
    counters_.receive_error_count = frame.data[7];
  }
  if ((frame.id & error_mask_) == 0) return;
  out.push_back(TimedCanFrame{frame, time_ns, /*tx_echo=*/false});
}

std::int64_t GsUsbBus::FrameTimeNs(const GsUsbHostFrame& host_frame, std::int64_t now_ns) {
  if (!host_frame.timestamp_us) {
    last_time_ns_ = std::max(now_ns, last_time_ns_);
    return last_time_ns_;
  }
  const GsUsbUnwrappedTime unwrapped = UnwrapGsUsbTimestamp(unwrapper_, *host_frame.timestamp_us);
  unwrapper_ = unwrapped.state;
  if (!device_to_host_offset_ns_) device_to_host_offset_ns_ = now_ns - unwrapped.time_ns;
  // Echoes and RX frames can be stamped a few µs out of order; the seam promises no decrease.
  last_time_ns_ = std::max(last_time_ns_, unwrapped.time_ns + *device_to_host_offset_ns_);
  return last_time_ns_;
}

void GsUsbBus::SetFilters(std::span<const CanFilter> filters) {
  filters_.assign(filters.begin(), filters.end());
}

void GsUsbBus::SetReceiveErrorFrames(bool enabled) { error_mask_ = enabled ? kCanErrMask : 0; }

void GsUsbBus::SetErrorFrameMask(std::uint32_t class_mask) {
  error_mask_ = class_mask & kCanErrMask;
}

Result<void> GsUsbBus::SetReceiveOwnFrames(bool enabled) {
  receive_own_frames_ = enabled;
  return {};
}

Result<std::unique_ptr<CanBus>> OpenGsUsb(const GsUsbOptions& options) {
  Result<std::unique_ptr<GsUsbTransport>> transport = OpenLibusbGsUsbTransport();
  if (!transport) return transport.error();
  Result<std::unique_ptr<GsUsbBus>> bus = GsUsbBus::Open(std::move(transport).value(), options);
  if (!bus) return bus.error();
  return std::unique_ptr<CanBus>(std::move(bus).value());
}

}  // namespace hilrig::rig
