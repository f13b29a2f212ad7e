// The serial line's half of a SerialDut (host/linked_dut/serial_dut.h): the HIL link's compact
// per-tick messages (SerialStep / SerialCommand, floats, the setpoint only with the fields that
// changed) in the framing of host/link/line_link.h, and the tactile CAN frames as a sensor node's
// UART bridge frames on a second line (or onto the DUT's own CAN bus). Open opens the lines and
// shakes hands: a runner Hello every hello interval until the DUT answers with the protocol version
// and, on a line anyone could reach, the run's token; then the firmware configuration until the DUT
// answers with its TargetInfo. A request holds the inputs since the last one; the line may lose a
// frame, so a request goes out again (led by a delimiter) when no answer came within the retry
// time, and a stray message is counted and set aside.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/link/dut_firmware.h"
#include "host/link/hil_link_codec.h"
#include "host/link/line_link.h"
#include "host/linked_dut/dut_link.h"
#include "host/linked_dut/serial_dut.h"
#include "proto/hil_link.pb.h"
#include "rig/value_counts.h"

namespace hilrig::host {

class SerialDutLink final : public DutLink {
 public:
  SerialDutLink(const DutFirmware& firmware, double control_period_s, SerialLineOpener open_lines,
                const SerialDutOptions& options);

  rig::Result<void> Open(const rig::Clock& clock) override;
  rig::Result<void> Input(const DutInput& input, bool realtime, std::int64_t sent_wall_ns) override;
  rig::Result<void> Request(const LinkRequest& request) override;
  std::optional<std::int64_t> resend_after_ns() const override { return retry_ns_; }
  rig::Result<void> Resend() override;
  DutLinkEvent Receive(int timeout_ms) override;
  rig::Result<ActuatorMessage> TakeAnswer(std::int64_t arrival_wall_ns) override;
  bool has_peer() const override { return lines_.emulator.has_value(); }
  std::optional<std::string> PeerExit() override;
  void Close(bool goodbye) override;
  std::string description() const override;
  std::string timeout_detail() const override;
  std::string metric_prefix() const override { return "line_"; }
  std::vector<rig::Metric> metrics(bool realtime) const override;
  std::optional<TargetSummary> target() const override;
  std::uint64_t sensor_bytes_missing() const override;

 private:
  rig::Result<void> Handshake(const rig::Clock& clock);
  // Sends `message` every `interval_ns` until `accept` takes an answer (true) or fails it.
  rig::Result<void> Exchange(
      const rig::Clock& clock, const proto::LinkMessage& message, std::int64_t interval_ns,
      std::int64_t deadline_ns, const char* waiting_for,
      const std::function<rig::Result<bool>(const proto::LinkMessage&)>& accept);
  void AddInput(const DutInput& input, std::int64_t now_ns, proto::SerialStep& step);
  // The frames onto the bridge line (returns the bytes written, which the step announces) or
  // onto the DUT's own CAN bus (returns 0: nothing to wait for).
  rig::Result<std::uint32_t> ForwardFrames(const std::vector<rig::TimedCanFrame>& frames,
                                           int timeout_ms);
  rig::Result<std::uint32_t> ForwardToCan(const std::vector<rig::TimedCanFrame>& frames);
  rig::Result<void> SendLine(const proto::LinkMessage& message, int timeout_ms, bool flush_first);
  // `seconds` plus twice the time `bytes` take on the line.
  std::int64_t RetryNs(double seconds, std::size_t bytes) const;

  DutFirmware firmware_;
  double control_period_s_;
  std::int64_t period_ns_;
  SerialLineOpener open_lines_;
  SerialDutOptions options_;

  SerialLines lines_;
  std::unique_ptr<LineLink> link_;
  LinkSequencer sequencer_;
  std::optional<proto::TargetInfo> target_info_;
  std::string dut_name_;

  std::vector<DutInput> pending_inputs_;
  std::optional<proto::SerialSetpoint> last_setpoint_;  // as last sent, every field set
  std::vector<std::uint8_t> bridge_bytes_;
  proto::LinkMessage step_;      // the last request, for a retry
  std::int64_t retry_ns_ = 0;    // after the last request
  proto::LinkMessage received_;  // the last kAnswer's message
  proto::SerialDutCounters dut_counters_;
  rig::ValueCounts work_cycles_;

  std::uint64_t hellos_sent_ = 0;
  std::uint64_t configs_sent_ = 0;
  std::uint64_t steps_sent_ = 0;
  std::uint64_t step_retries_ = 0;
  std::uint64_t unexpected_messages_ = 0;  // well-framed messages that were not an answer
  std::uint64_t bridge_frames_ = 0;
  std::uint64_t bridge_bytes_sent_ = 0;
  std::uint64_t bridge_frames_dropped_ = 0;  // no bridge wired, or a frame it cannot carry
  std::uint64_t can_frames_forwarded_ = 0;   // onto lines_.can
};

}  // namespace hilrig::host
