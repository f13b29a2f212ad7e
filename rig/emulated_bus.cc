#include "rig/emulated_bus.h"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <vector>

#include "rig/check.h"
#include "rig/ring_buffer.h"

namespace hilrig::rig {
namespace {

// Fault confinement thresholds of ISO 11898-1.
constexpr std::uint32_t kWarningLimit = 96;
constexpr std::uint32_t kPassiveLimit = 128;
constexpr std::uint32_t kBusOffLimit = 256;
constexpr std::uint32_t kTransmitErrorStep = 8;
constexpr std::int64_t kBusOffRecoveryBits = 128 * 11;

struct PendingFrame {
  CanFrame frame;
  std::int64_t queued_ns = 0;
};

// Lower wins, as dominant bits win on the wire: base id, then RTR (standard) or SRR (extended,
// always recessive), then IDE, then the 18 extension bits and the extended RTR. Error frames
// override arbitration altogether.
std::uint64_t ArbitrationKey(const CanFrame& frame) {
  if (frame.error) return 0;
  const std::uint64_t rtr = frame.remote ? 1 : 0;
  if (!frame.extended) return 1 + ((std::uint64_t{frame.id} << 21) | (rtr << 20));
  const std::uint64_t base = frame.id >> 18;
  const std::uint64_t extension = frame.id & 0x3FFFF;
  return 1 + ((base << 21) | (1ULL << 20) | (1ULL << 19) | (extension << 1) | rtr);
}

BusState StateFor(std::uint32_t tec, std::uint32_t rec) {
  if (tec >= kBusOffLimit) return BusState::kBusOff;
  if (std::max(tec, rec) >= kPassiveLimit) return BusState::kErrorPassive;
  if (std::max(tec, rec) >= kWarningLimit) return BusState::kErrorWarning;
  return BusState::kErrorActive;
}

std::uint64_t IdKey(std::uint32_t id, bool extended) {
  return (std::uint64_t{extended} << 32) | id;
}

}  // namespace

class EmulatedEndpoint;

// Frames an endpoint (or the bus itself, owner == nullptr) wants on the wire, oldest first.
struct TxSource {
  RingBuffer<PendingFrame> queue;
  EmulatedEndpoint* owner = nullptr;
};

class EmulatedMedium {
 public:
  explicit EmulatedMedium(const EmulatedBusConfig& config);
  ~EmulatedMedium();

  void Attach(EmulatedEndpoint* endpoint);
  void Detach(EmulatedEndpoint* endpoint);
  EmulatedEndpoint* Find(std::string_view name) const;

  // Decides every transmission that starts before now_ns, and returns the time new frames are
  // queued at: now_ns, or the latest time seen if now_ns is earlier.
  std::int64_t AdvanceTo(std::int64_t now_ns) {
    latest_now_ns_ = std::max(latest_now_ns_, now_ns);
    if (next_start_bound_ns_ < latest_now_ns_) TransmitUntilLatestNow();
    return latest_now_ns_;
  }
  // A frame joined a TX queue at queued_ns: the next transmission may start as early as that.
  void NoteQueued(std::int64_t queued_ns) {
    next_start_bound_ns_ = std::min(next_start_bound_ns_, queued_ns);
  }
  void InjectErrorFrame(const CanFrame& frame, std::int64_t now_ns);

  const EmulatedBusConfig& config() const { return config_; }
  const EmulatedBusStats& stats() const { return stats_; }
  std::int64_t bus_off_recovery_ns() const { return bus_off_recovery_ns_; }

 private:
  // The queue head that wins arbitration at start_ns, or null if none is waiting by then.
  TxSource* Arbitrate(std::int64_t start_ns) const;
  // The non-empty TX queues: how many, the first of them, and the earliest time any of their
  // frames wants the wire (max if nothing is queued).
  struct QueueHeads {
    std::int64_t earliest_ns = std::numeric_limits<std::int64_t>::max();
    std::size_t waiting = 0;
    TxSource* first = nullptr;
  };
  QueueHeads ScanQueueHeads() const;
  void TransmitUntilLatestNow();
  void Transmit(TxSource& source, std::int64_t start_ns);
  void TransmitCorrupted(TxSource& source, std::int64_t start_ns, std::int64_t duration_ns);
  void Deliver(const EmulatedEndpoint* sender, const CanFrame& frame, std::int64_t end_ns,
               bool dropped);
  void RecordWire(std::int64_t start_ns, std::int64_t end_ns);
  void RecordQueueing(const CanFrame& frame, std::int64_t queueing_ns);
  IdQueueingStats& QueueingStatsFor(std::uint32_t id, bool extended);
  std::int64_t DurationNs(const CanFrame& frame) const;

  EmulatedBusConfig config_;
  FaultStream faults_;
  std::vector<EmulatedEndpoint*> endpoints_;
  // The bus's own injector first, then one per endpoint in connection order (the tie-break).
  std::vector<TxSource*> sources_;
  TxSource injector_;
  std::int64_t latest_now_ns_ = std::numeric_limits<std::int64_t>::min();
  std::int64_t bus_free_at_ns_ = 0;
  // No transmission starts before this (a lower bound; frames leaving a queue unsent only make
  // the true start later). Most ticks poll a bus with nothing due, and this answers them without
  // looking at every queue.
  std::int64_t next_start_bound_ns_ = std::numeric_limits<std::int64_t>::max();
  std::int64_t error_flag_ns_;
  std::int64_t bus_off_recovery_ns_;
  // FrameDurationNs of a classic data frame, by [extended][length], filled once: nearly all
  // traffic is such frames, and their duration depends on nothing else.
  std::array<std::array<std::int64_t, CanFrame::kMaxClassicPayload + 1>, 2> classic_data_ns_{};
  EmulatedBusStats stats_;
  // Position + 1 in stats_.queueing_by_id of each standard id seen, 0 for one not seen. Standard
  // ids sort before extended ones, so their positions stay below 2048 and only move when another
  // standard id is first seen.
  std::array<std::uint16_t, kMaxStandardId + 1> standard_queueing_slot_{};
};

class EmulatedEndpoint final : public CanBus {
 public:
  EmulatedEndpoint(EmulatedMedium& medium, std::string name)
      : medium_(medium),
        name_(std::move(name)),
        receive_own_frames_(medium.config().receive_own_frames) {
    tx_.owner = this;
    medium_.Attach(this);
  }
  ~EmulatedEndpoint() override { medium_.Detach(this); }
  EmulatedEndpoint(const EmulatedEndpoint&) = delete;
  EmulatedEndpoint& operator=(const EmulatedEndpoint&) = delete;

  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override {
    const std::int64_t queued_ns = medium_.AdvanceTo(now_ns);
    MaybeRestart(queued_ns);
    // The test without a message first: every frame sent passes it, and only a refusal needs
    // the reason.
    if (!IsValidFrame(frame) || bus_off() || tx_.queue.size() >= tx_capacity_) [[unlikely]] {
      ++counters_.send_failures;
      return CheckSendable(frame);
    }
    PendingFrame& pending = tx_.queue.AppendSlot();
    pending.frame = frame;
    pending.queued_ns = queued_ns;
    medium_.NoteQueued(queued_ns);
    ++counters_.frames_sent;
    return {};
  }

  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override {
    medium_.AdvanceTo(now_ns);
    MaybeRestart(now_ns);
    const std::size_t appended =
        rx_.PopFrontInto(out, [now_ns](const TimedCanFrame& f) { return f.time_ns <= now_ns; });
    counters_.frames_received += appended;
    return appended;
  }

  void SetFilters(std::span<const CanFilter> filters) override {
    filters_.assign(filters.begin(), filters.end());
  }
  void SetReceiveErrorFrames(bool enabled) override { error_mask_ = enabled ? kCanErrMask : 0; }
  void SetErrorFrameMask(std::uint32_t class_mask) override { error_mask_ = class_mask; }
  Result<void> SetReceiveOwnFrames(bool enabled) override {
    receive_own_frames_ = enabled;
    return {};
  }
  BusState state() const override { return state_; }
  BusCounters counters() const override {
    BusCounters counters = counters_;
    counters.transmit_error_count = tec_;
    counters.receive_error_count = rec_;
    return counters;
  }

  const std::string& name() const { return name_; }
  TxSource& tx() { return tx_; }
  bool bus_off() const { return state_ == BusState::kBusOff; }

  // A frame from the wire; own_frame marks the echo of this endpoint's transmission.
  void Accept(const CanFrame& frame, std::int64_t time_ns, bool own_frame) {
    if (own_frame && !receive_own_frames_) return;
    if (!Wants(frame)) return;
    if (rx_.size() >= rx_capacity_) {
      ++counters_.frames_dropped_rx_overflow;
      return;
    }
    TimedCanFrame& received = rx_.AppendSlot();
    received.frame = frame;
    received.time_ns = time_ns;
    received.tx_echo = own_frame;
    latest_rx_ns_ = time_ns;
  }

  // Fault confinement bookkeeping, all at time_ns.
  void CountTransmitSuccess(std::int64_t time_ns) {
    if (tec_ == 0) return;
    --tec_;
    UpdateState(time_ns);
  }
  void CountReceiveSuccess(std::int64_t time_ns) {
    if (rec_ == 0) return;
    --rec_;
    UpdateState(time_ns);
  }
  void CountProtocolError(bool transmitting, std::int64_t time_ns) {
    if (transmitting) {
      tec_ += kTransmitErrorStep;
    } else {
      rec_ = std::min(rec_ + 1, kPassiveLimit);  // REC stops growing once error-passive
    }
    std::array<std::uint8_t, 8> data{};
    data[2] = transmitting ? can_error::kProtTypeTx : can_error::kProtTypeUnspecified;
    data[3] = can_error::kProtLocCrcSequence;
    ReportError(can_error::kProtocol | can_error::kBusError, data, time_ns);
    UpdateState(time_ns);
  }
  void ForceBusOff(std::int64_t time_ns) {
    tec_ = std::max(tec_, kBusOffLimit);
    UpdateState(time_ns);
  }
  void Restart(std::int64_t time_ns) {
    if (!bus_off()) return;
    tec_ = rec_ = 0;
    state_ = BusState::kErrorActive;
    ReportError(can_error::kRestarted, {}, time_ns);
  }
  // Automatic recovery due by time_ns happens at its due time, before anything later.
  void MaybeRestart(std::int64_t time_ns) {
    if (bus_off() && medium_.config().bus_off_restart_ns > 0 && time_ns >= restart_due_ns_) {
      Restart(restart_due_ns_);
    }
  }

 private:
  // Why a frame cannot be sent now, or ok.
  Result<void> CheckSendable(const CanFrame& frame) const {
    if (!IsValidFrame(frame)) return MakeError(name_ + ": " + ValidateFrame(frame).error().message);
    if (bus_off()) return MakeError(name_ + ": controller is bus-off, frame not sent");
    if (tx_.queue.size() >= tx_capacity_) {
      return MakeError(name_ + ": TX queue full (" + std::to_string(tx_.queue.size()) +
                       " frames waiting for the bus)");
    }
    return {};
  }

  bool Wants(const CanFrame& frame) const {
    if (frame.error) return (frame.id & error_mask_) != 0;
    return filters_.empty() || FilterAccepts(filters_, frame);
  }

  // Reports each change of fault confinement state as Linux drivers do.
  void UpdateState(std::int64_t time_ns) {
    const BusState next = StateFor(tec_, rec_);
    if (next == state_) return;
    state_ = next;
    if (next == BusState::kBusOff) {
      EnterBusOff(time_ns);
      return;
    }
    std::array<std::uint8_t, 8> data{};
    if (next == BusState::kErrorActive) {
      data[1] = can_error::kCtrlActive;
    } else if (next == BusState::kErrorPassive) {
      data[1] = (tec_ >= kPassiveLimit ? can_error::kCtrlTxPassive : 0) |
                (rec_ >= kPassiveLimit ? can_error::kCtrlRxPassive : 0);
    } else {
      data[1] = (tec_ >= kWarningLimit ? can_error::kCtrlTxWarning : 0) |
                (rec_ >= kWarningLimit ? can_error::kCtrlRxWarning : 0);
    }
    ReportError(can_error::kController, data, time_ns);
  }

  void EnterBusOff(std::int64_t time_ns) {
    counters_.frames_dropped_tx += tx_.queue.size();
    while (!tx_.queue.empty()) tx_.queue.pop_front();
    restart_due_ns_ =
        time_ns + std::max(medium_.config().bus_off_restart_ns, medium_.bus_off_recovery_ns());
    ReportError(can_error::kBusOff, {}, time_ns);
  }

  // Every controller error frame carries the counters, as most Linux drivers add CAN_ERR_CNT.
  // A state forced in the middle of a frame this endpoint has already been handed is reported
  // when that frame ends, which keeps the RX queue in time order.
  void ReportError(std::uint32_t class_bits, std::array<std::uint8_t, 8> data,
                   std::int64_t time_ns) {
    data[6] = static_cast<std::uint8_t>(std::min<std::uint32_t>(tec_, 255));
    data[7] = static_cast<std::uint8_t>(std::min<std::uint32_t>(rec_, 255));
    Accept(CanFrame::ErrorFrame(class_bits | can_error::kCounters, data),
           std::max(time_ns, latest_rx_ns_), false);
  }

  EmulatedMedium& medium_;
  std::string name_;
  std::vector<CanFilter> filters_;
  std::uint32_t error_mask_ = 0;
  bool receive_own_frames_;
  TxSource tx_;
  RingBuffer<TimedCanFrame> rx_;
  // The medium's queue capacities, read on every frame.
  std::size_t tx_capacity_ = medium_.config().tx_queue_capacity;
  std::size_t rx_capacity_ = medium_.config().rx_queue_capacity;
  std::int64_t latest_rx_ns_ = std::numeric_limits<std::int64_t>::min();
  BusCounters counters_;
  std::uint32_t tec_ = 0;
  std::uint32_t rec_ = 0;
  BusState state_ = BusState::kErrorActive;
  std::int64_t restart_due_ns_ = 0;
};

EmulatedMedium::EmulatedMedium(const EmulatedBusConfig& config)
    : config_(config), faults_(config.faults) {
  HILRIG_CHECK(config.nominal_bitrate_bps > 0 && config.data_bitrate_bps > 0,
               "EmulatedBus bitrates must be positive");
  HILRIG_CHECK(config.rx_queue_capacity > 0, "EmulatedBus rx_queue_capacity must be positive");
  HILRIG_CHECK(config.tx_queue_capacity > 0, "EmulatedBus tx_queue_capacity must be positive");
  HILRIG_CHECK(config.bus_off_restart_ns >= 0, "EmulatedBus bus_off_restart_ns must be >= 0");
  error_flag_ns_ = FrameDurationNs(CanFrame::ErrorFrame(0, {}), config.nominal_bitrate_bps,
                                   config.nominal_bitrate_bps);
  bus_off_recovery_ns_ = (kBusOffRecoveryBits * 1'000'000'000 + config.nominal_bitrate_bps - 1) /
                         config.nominal_bitrate_bps;
  for (const bool extended : {false, true}) {
    for (std::size_t length = 0; length <= CanFrame::kMaxClassicPayload; ++length) {
      CanFrame frame;
      frame.extended = extended;
      frame.length = static_cast<std::uint8_t>(length);
      classic_data_ns_[extended][length] =
          FrameDurationNs(frame, config.nominal_bitrate_bps, config.data_bitrate_bps);
    }
  }
  sources_.push_back(&injector_);
}

EmulatedMedium::~EmulatedMedium() {
  if (endpoints_.empty()) return;
  std::string names;
  for (const EmulatedEndpoint* endpoint : endpoints_) names += " " + endpoint->name();
  HILRIG_CHECK(endpoints_.empty(),
               "EmulatedBus destroyed while endpoints still connected:" + names);
}

void EmulatedMedium::Attach(EmulatedEndpoint* endpoint) {
  endpoints_.push_back(endpoint);
  sources_.push_back(&endpoint->tx());
}

void EmulatedMedium::Detach(EmulatedEndpoint* endpoint) {
  const auto it = std::find(endpoints_.begin(), endpoints_.end(), endpoint);
  HILRIG_CHECK(it != endpoints_.end(), "detaching an endpoint that is not attached");
  endpoints_.erase(it);
  sources_.erase(std::find(sources_.begin(), sources_.end(), &endpoint->tx()));
}

EmulatedEndpoint* EmulatedMedium::Find(std::string_view name) const {
  const auto it = std::find_if(endpoints_.begin(), endpoints_.end(),
                               [name](const EmulatedEndpoint* e) { return e->name() == name; });
  return it == endpoints_.end() ? nullptr : *it;
}

void EmulatedMedium::TransmitUntilLatestNow() {
  while (true) {
    const QueueHeads heads = ScanQueueHeads();
    const std::int64_t start_ns = std::max(bus_free_at_ns_, heads.earliest_ns);
    if (start_ns >= latest_now_ns_) {  // also when nothing is queued (max)
      next_start_bound_ns_ = start_ns;
      return;
    }
    // A lone waiting frame wins without a contest (a scene's nodes often share one endpoint).
    Transmit(heads.waiting == 1 ? *heads.first : *Arbitrate(start_ns), start_ns);
  }
}

void EmulatedMedium::InjectErrorFrame(const CanFrame& frame, std::int64_t now_ns) {
  const std::int64_t queued_ns = AdvanceTo(now_ns);
  injector_.queue.push_back({frame, queued_ns});
  NoteQueued(queued_ns);
}

EmulatedMedium::QueueHeads EmulatedMedium::ScanQueueHeads() const {
  QueueHeads heads;
  for (TxSource* source : sources_) {
    if (source->queue.empty()) continue;
    heads.earliest_ns = std::min(heads.earliest_ns, source->queue.front().queued_ns);
    if (heads.waiting++ == 0) heads.first = source;
  }
  return heads;
}

TxSource* EmulatedMedium::Arbitrate(std::int64_t start_ns) const {
  TxSource* winner = nullptr;
  std::uint64_t winner_key = std::numeric_limits<std::uint64_t>::max();
  for (TxSource* source : sources_) {
    if (source->queue.empty() || source->queue.front().queued_ns > start_ns) continue;
    const std::uint64_t key = ArbitrationKey(source->queue.front().frame);
    if (winner == nullptr || key < winner_key) {
      winner = source;
      winner_key = key;
    }
  }
  HILRIG_CHECK(winner != nullptr, "arbitration without a waiting frame");
  return winner;
}

void EmulatedMedium::Transmit(TxSource& source, std::int64_t start_ns) {
  // By reference, not a copy of the 80-byte frame: delivery only appends to RX queues and counts
  // successes down (which never reaches bus-off), so the TX queue head stays put until popped.
  const PendingFrame& pending = source.queue.front();
  const std::int64_t duration_ns = DurationNs(pending.frame);
  const WireFault fault = pending.frame.error ? WireFault::kNone : faults_.Next();
  if (fault == WireFault::kCorrupt) {
    TransmitCorrupted(source, start_ns, duration_ns);
    return;
  }
  const std::int64_t end_ns = start_ns + duration_ns;
  RecordWire(start_ns, end_ns);
  if (!pending.frame.error) RecordQueueing(pending.frame, start_ns - pending.queued_ns);
  if (fault == WireFault::kDrop) ++stats_.frames_dropped;
  Deliver(source.owner, pending.frame, end_ns, fault == WireFault::kDrop);
  source.queue.pop_front();
}

// The frame stays queued: its sender retransmits it unless the error took it bus-off.
void EmulatedMedium::TransmitCorrupted(TxSource& source, std::int64_t start_ns,
                                       std::int64_t duration_ns) {
  const std::int64_t end_ns = start_ns + duration_ns + error_flag_ns_;
  RecordWire(start_ns, end_ns);
  ++stats_.frames_corrupted;
  for (EmulatedEndpoint* endpoint : endpoints_) {
    endpoint->MaybeRestart(end_ns);
    if (!endpoint->bus_off()) endpoint->CountProtocolError(endpoint == source.owner, end_ns);
  }
}

void EmulatedMedium::Deliver(const EmulatedEndpoint* sender, const CanFrame& frame,
                             std::int64_t end_ns, bool dropped) {
  for (EmulatedEndpoint* endpoint : endpoints_) {
    endpoint->MaybeRestart(end_ns);
    if (endpoint->bus_off()) continue;
    if (endpoint == sender) {
      if (!frame.error) endpoint->CountTransmitSuccess(end_ns);
      endpoint->Accept(frame, end_ns, /*own_frame=*/true);
    } else if (!dropped) {
      if (!frame.error) endpoint->CountReceiveSuccess(end_ns);
      endpoint->Accept(frame, end_ns, /*own_frame=*/false);
    }
  }
}

void EmulatedMedium::RecordWire(std::int64_t start_ns, std::int64_t end_ns) {
  bus_free_at_ns_ = end_ns;
  ++stats_.frames;
  stats_.busy_ns += end_ns - start_ns;
}

// Every frame on the queues passed IsValidFrame, so a classic one has at most 8 bytes.
std::int64_t EmulatedMedium::DurationNs(const CanFrame& frame) const {
  if (!frame.fd && !frame.remote && !frame.error)
    return classic_data_ns_[frame.extended][frame.length];
  return FrameDurationNs(frame, config_.nominal_bitrate_bps, config_.data_bitrate_bps);
}

void EmulatedMedium::RecordQueueing(const CanFrame& frame, std::int64_t queueing_ns) {
  // A standard id seen before is one look-up away; the search is for the rest.
  const std::uint16_t slot = frame.extended ? 0 : standard_queueing_slot_[frame.id];
  IdQueueingStats& stats =
      slot != 0 ? stats_.queueing_by_id[slot - 1] : QueueingStatsFor(frame.id, frame.extended);
  ++stats.frames;
  stats.total_queueing_ns += queueing_ns;
  stats.max_queueing_ns = std::max(stats.max_queueing_ns, queueing_ns);
}

// A sorted vector: it only grows when an id is seen for the first time, so steady traffic does
// not allocate; standard ids (valid, so at most kMaxStandardId) skip the search.
IdQueueingStats& EmulatedMedium::QueueingStatsFor(std::uint32_t id, bool extended) {
  std::vector<IdQueueingStats>& by_id = stats_.queueing_by_id;
  if (!extended && standard_queueing_slot_[id] != 0) return by_id[standard_queueing_slot_[id] - 1];
  const std::uint64_t key = IdKey(id, extended);
  auto it = std::lower_bound(
      by_id.begin(), by_id.end(), key,
      [](const IdQueueingStats& s, std::uint64_t k) { return IdKey(s.id, s.extended) < k; });
  if (it == by_id.end() || IdKey(it->id, it->extended) != key) {
    it = by_id.insert(it, IdQueueingStats{.id = id, .extended = extended});
  }
  if (!extended) {
    for (std::size_t i = 0; i < by_id.size() && !by_id[i].extended; ++i) {
      standard_queueing_slot_[by_id[i].id] = static_cast<std::uint16_t>(i + 1);
    }
  }
  return *it;
}

std::int64_t IdQueueingStats::mean_queueing_ns() const {
  return frames == 0 ? 0 : total_queueing_ns / static_cast<std::int64_t>(frames);
}

double EmulatedBusStats::LoadOver(std::int64_t elapsed_ns) const {
  return elapsed_ns > 0 ? static_cast<double>(busy_ns) / static_cast<double>(elapsed_ns) : 0.0;
}

const IdQueueingStats* EmulatedBusStats::QueueingFor(std::uint32_t id, bool extended) const {
  const auto it =
      std::find_if(queueing_by_id.begin(), queueing_by_id.end(),
                   [&](const IdQueueingStats& s) { return s.id == id && s.extended == extended; });
  return it == queueing_by_id.end() ? nullptr : &*it;
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

void EmulatedBus::AdvanceTo(std::int64_t now_ns) {
  HILRIG_CHECK(medium_ != nullptr, "AdvanceTo on a moved-from EmulatedBus");
  medium_->AdvanceTo(now_ns);
}

EmulatedBusStats EmulatedBus::stats() const {
  HILRIG_CHECK(medium_ != nullptr, "stats on a moved-from EmulatedBus");
  return medium_->stats();
}

Result<void> EmulatedBus::InjectErrorFrame(const CanFrame& error_frame, std::int64_t now_ns) {
  HILRIG_CHECK(medium_ != nullptr, "InjectErrorFrame on a moved-from EmulatedBus");
  if (!error_frame.error) return MakeError("InjectErrorFrame needs an error frame");
  if (Result<void> valid = ValidateFrame(error_frame); !valid) return valid;
  medium_->InjectErrorFrame(error_frame, now_ns);
  return {};
}

Result<void> EmulatedBus::ForceBusOff(std::string_view endpoint_name, std::int64_t now_ns) {
  HILRIG_CHECK(medium_ != nullptr, "ForceBusOff on a moved-from EmulatedBus");
  EmulatedEndpoint* endpoint = medium_->Find(endpoint_name);
  if (endpoint == nullptr) return MakeError("no endpoint named " + std::string(endpoint_name));
  endpoint->ForceBusOff(medium_->AdvanceTo(now_ns));
  return {};
}

Result<void> EmulatedBus::RestartEndpoint(std::string_view endpoint_name, std::int64_t now_ns) {
  HILRIG_CHECK(medium_ != nullptr, "RestartEndpoint on a moved-from EmulatedBus");
  EmulatedEndpoint* endpoint = medium_->Find(endpoint_name);
  if (endpoint == nullptr) return MakeError("no endpoint named " + std::string(endpoint_name));
  endpoint->Restart(medium_->AdvanceTo(now_ns));
  return {};
}

}  // namespace hilrig::rig
