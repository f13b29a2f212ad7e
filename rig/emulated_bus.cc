#include "rig/emulated_bus.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "rig/check.h"
#include "rig/ring_buffer.h"

namespace hilrig::rig {

class EmulatedEndpoint;

class EmulatedMedium {
 public:
  explicit EmulatedMedium(const EmulatedBusConfig& config);
  ~EmulatedMedium();

  void Attach(EmulatedEndpoint* endpoint);
  void Detach(EmulatedEndpoint* endpoint);
  // Puts a valid frame on the wire and hands it to the receiving endpoints.
  void Transmit(const EmulatedEndpoint* sender, const CanFrame& frame, std::int64_t now_ns);

  const EmulatedBusConfig& config() const { return config_; }
  EmulatedBusStats stats() const { return stats_; }

 private:
  // The scheduling seam: returns when the frame finishes on the wire. Arbitration, fault
  // injection and TX queue limits will replace this first-come-first-served rule.
  std::int64_t ScheduleOnWire(const CanFrame& frame, std::int64_t now_ns);

  EmulatedBusConfig config_;
  std::vector<EmulatedEndpoint*> endpoints_;
  std::int64_t bus_free_at_ns_ = 0;
  EmulatedBusStats stats_;
};

class EmulatedEndpoint final : public CanBus {
 public:
  EmulatedEndpoint(EmulatedMedium& medium, std::string name)
      : medium_(medium), name_(std::move(name)) {
    medium_.Attach(this);
  }
  ~EmulatedEndpoint() override { medium_.Detach(this); }
  EmulatedEndpoint(const EmulatedEndpoint&) = delete;
  EmulatedEndpoint& operator=(const EmulatedEndpoint&) = delete;

  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override {
    Result<void> valid = ValidateFrame(frame);
    if (!valid) {
      ++counters_.send_failures;
      return MakeError(name_ + ": " + valid.error().message);
    }
    medium_.Transmit(this, frame, now_ns);
    ++counters_.frames_sent;
    return {};
  }

  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override {
    std::size_t appended = 0;
    while (!rx_.empty() && rx_.front().time_ns <= now_ns) {
      out.push_back(rx_.front());
      rx_.pop_front();
      ++appended;
    }
    counters_.frames_received += appended;
    return appended;
  }

  void SetFilters(std::span<const CanFilter> filters) override {
    filters_.assign(filters.begin(), filters.end());
  }
  void SetReceiveErrorFrames(bool enabled) override { receive_error_frames_ = enabled; }
  // Always error-active until fault injection exists to drive the error counters.
  BusState state() const override { return BusState::kErrorActive; }
  BusCounters counters() const override { return counters_; }

  const std::string& name() const { return name_; }

  void Deliver(const TimedCanFrame& timed) {
    if (!Wants(timed.frame)) return;
    if (rx_.size() >= medium_.config().rx_queue_capacity) {
      ++counters_.frames_dropped_rx_overflow;
      return;
    }
    rx_.push_back(timed);
  }

 private:
  bool Wants(const CanFrame& frame) const {
    return frame.error ? receive_error_frames_ : FilterAccepts(filters_, frame);
  }

  EmulatedMedium& medium_;
  std::string name_;
  std::vector<CanFilter> filters_;
  bool receive_error_frames_ = false;
  RingBuffer<TimedCanFrame> rx_;
  BusCounters counters_;
};

EmulatedMedium::EmulatedMedium(const EmulatedBusConfig& config) : config_(config) {
  HILRIG_CHECK(config.nominal_bitrate_bps > 0 && config.data_bitrate_bps > 0,
               "EmulatedBus bitrates must be positive");
  HILRIG_CHECK(config.rx_queue_capacity > 0, "EmulatedBus rx_queue_capacity must be positive");
}

EmulatedMedium::~EmulatedMedium() {
  if (endpoints_.empty()) return;
  std::string names;
  for (const EmulatedEndpoint* endpoint : endpoints_) names += " " + endpoint->name();
  HILRIG_CHECK(endpoints_.empty(),
               "EmulatedBus destroyed while endpoints still connected:" + names);
}

void EmulatedMedium::Attach(EmulatedEndpoint* endpoint) { endpoints_.push_back(endpoint); }

void EmulatedMedium::Detach(EmulatedEndpoint* endpoint) {
  const auto it = std::find(endpoints_.begin(), endpoints_.end(), endpoint);
  HILRIG_CHECK(it != endpoints_.end(), "detaching an endpoint that is not attached");
  endpoints_.erase(it);
}

void EmulatedMedium::Transmit(const EmulatedEndpoint* sender, const CanFrame& frame,
                              std::int64_t now_ns) {
  const TimedCanFrame timed{frame, ScheduleOnWire(frame, now_ns)};
  for (EmulatedEndpoint* endpoint : endpoints_) {
    if (endpoint != sender || config_.receive_own_frames) endpoint->Deliver(timed);
  }
}

std::int64_t EmulatedMedium::ScheduleOnWire(const CanFrame& frame, std::int64_t now_ns) {
  const std::int64_t duration_ns =
      FrameDurationNs(frame, config_.nominal_bitrate_bps, config_.data_bitrate_bps);
  const std::int64_t start_ns = std::max(now_ns, bus_free_at_ns_);
  bus_free_at_ns_ = start_ns + duration_ns;
  ++stats_.frames;
  stats_.busy_ns += duration_ns;
  return bus_free_at_ns_;
}

EmulatedBus::EmulatedBus(EmulatedBusConfig config)
    : medium_(std::make_unique<EmulatedMedium>(config)) {}

EmulatedBus::~EmulatedBus() = default;
EmulatedBus::EmulatedBus(EmulatedBus&&) noexcept = default;

EmulatedBus& EmulatedBus::operator=(EmulatedBus&& other) noexcept {
  medium_ = std::move(other.medium_);  // the old medium checks it has no endpoints left
  return *this;
}

std::unique_ptr<CanBus> EmulatedBus::Connect(std::string name) {
  HILRIG_CHECK(medium_ != nullptr, "Connect on a moved-from EmulatedBus");
  return std::make_unique<EmulatedEndpoint>(*medium_, std::move(name));
}

EmulatedBusStats EmulatedBus::stats() const {
  HILRIG_CHECK(medium_ != nullptr, "stats on a moved-from EmulatedBus");
  return medium_->stats();
}

}  // namespace hilrig::rig
