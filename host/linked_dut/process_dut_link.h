// The process link's half of a ProcessDut (host/linked_dut/process_dut.h): dut_emu, a user's
// program or a DUT that dialled in, on the HIL link over shared memory or TCP. Open launches or
// awaits the DUT (host/linked_dut/process_dut_launch.h), proves it and sends the runner's hello and
// the firmware. A lockstep request carries the inputs queued since the last one, and the tick's CAN
// frames (in the request, or onto the forward bus), in one write; in real time every message goes
// out at once and never waits for the socket. Any message but a command fails the run. In real time
// the wall send time of each input and frame waits in a bounded ring until a command says it
// consumed them, which makes the per-stream response latencies.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/link/child_process.h"
#include "host/link/hil_link_codec.h"
#include "host/link/hil_link_socket.h"
#include "host/linked_dut/dut_link.h"
#include "host/linked_dut/process_dut.h"
#include "proto/hil_link.pb.h"
#include "rig/can_bus.h"
#include "rig/duration_histogram.h"
#include "rig/ring_buffer.h"

namespace hilrig::host {

class ProcessDutLink final : public DutLink {
 public:
  ProcessDutLink(const DutFirmware& firmware, double control_period_s,
                 const ProcessDutOptions& options);

  rig::Result<void> Open(const rig::Clock& clock) override;
  rig::Result<void> Input(const DutInput& input, bool realtime, std::int64_t sent_wall_ns) override;
  rig::Result<void> Request(const LinkRequest& request) override;
  DutLinkEvent Receive(int timeout_ms) override;
  rig::Result<ActuatorMessage> TakeAnswer(std::int64_t arrival_wall_ns) override;
  bool has_peer() const override { return child_.has_value(); }
  std::optional<std::string> PeerExit() override;
  void Close(bool goodbye) override;
  std::string description() const override;
  std::string metric_prefix() const override { return "link_"; }
  std::vector<rig::Metric> metrics(bool realtime) const override;
  std::vector<StreamLatency> input_latencies() const override;
  std::optional<proto::DutFrontEndCounters> front_end_counters() const override {
    return front_end_;
  }

  // -1 before Open, or for a DUT that dialled in.
  pid_t pid() const { return child_ ? child_->pid() : -1; }

 private:
  // Wall send times of one stream's messages, keyed by sequence (CAN: frame count), until a
  // command covers them. Bounded: past kMaxPending the oldest is dropped, unmeasured.
  struct SendLog {
    struct Sent {
      std::uint64_t key = 0;
      std::int64_t wall_ns = 0;
    };
    rig::RingBuffer<Sent> pending;
    rig::DurationHistogram latency;
    bool used = false;  // anything sent on the stream
  };
  rig::Result<void> Send(const proto::LinkMessage& message, bool realtime);
  // Puts one frame on its way: into the request (no forward bus) or onto the bus.
  rig::Result<void> HandOver(const rig::TimedCanFrame& timed, proto::StepRequest& step);
  void LogSend(SendLog& log, std::uint64_t key, std::int64_t wall_ns);
  void Cover(SendLog& log, std::uint64_t up_to_key, std::int64_t arrival_wall_ns);
  void RecordCoverage(const proto::ActuatorCommand& command, std::int64_t arrival_wall_ns);

  DutFirmware firmware_;
  double control_period_s_;
  ProcessDutOptions options_;
  bool realtime_ = false;  // measures latencies

  std::optional<ChildProcess> child_;         // set by Open, unless the DUT dialled in
  std::unique_ptr<LinkConnection> link_;      // set by Open
  std::unique_ptr<rig::CanBus> forward_bus_;  // null: the frames ride in the step requests
  LinkSequencer sequencer_;
  proto::LinkMessage received_;  // the last kAnswer's message
  std::uint64_t can_frames_forwarded_ = 0;
  std::array<SendLog, kDutInputStreams> input_logs_;  // by DutInput alternative
  SendLog can_log_;  // keyed by the running count of frames forwarded
  std::uint64_t latency_samples_dropped_ = 0;
  std::uint64_t dut_frame_waits_expired_ = 0;
  std::uint64_t dut_frames_dropped_foreign_ = 0;         // forged datagrams the DUT's bus dropped
  std::uint64_t dut_frames_dropped_malformed_ = 0;       // datagrams no frame could be read from
  std::optional<proto::DutFrontEndCounters> front_end_;  // the DUT's, from its last command
  // Connections to the link port that did not prove the token, and who they were.
  std::uint64_t peers_refused_ = 0;
  std::string peers_refused_summary_;
};

}  // namespace hilrig::host
