// A DUT's traffic in the run's log (run.mcap), as `hilrig replay` reads it back: each input on
// /dut/in/<stream> (imu, vio, setpoint, mag, baro, gnss) as the HIL link's own message
// (proto/hil_link.proto's ImuSample, VioPose, ...), each CAN frame the DUT took on /dut/in/can with
// what the tactile protocol reads in it, each step asked on /dut/in/step and each command on
// /dut/out/command, at their simulated times; the run's spec once on /run/recording. A stream's
// channel is added with its first message, so a log has only the streams its DUT took.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "host/dut/dut_traffic.h"
#include "host/replay/traffic_wire.h"
#include "host/report/run_log.h"
#include "proto/run_log.pb.h"

namespace hilrig::host {

// The topics, for the reader.
inline constexpr const char* kRecordingTopic = "/run/recording";
inline constexpr const char* kDutInputTopicPrefix = "/dut/in/";  // + DutInput's kStream
inline constexpr const char* kDutCanTopic = "/dut/in/can";
inline constexpr const char* kDutStepTopic = "/dut/in/step";
inline constexpr const char* kDutCommandTopic = "/dut/out/command";

class DutTrafficLog final : public DutTrafficSink {
 public:
  // Logs `recording` on /run/recording at time 0. `log` must outlive this. Fails when the log's
  // stream does.
  static rig::Result<std::unique_ptr<DutTrafficLog>> Open(RunLogWriter& log,
                                                          const proto::RunRecording& recording);

  // Each writes the message's wire bytes (host/replay/traffic_wire.h) and logs them: no
  // allocation once every channel has had its first message (the log's chunks aside).
  void Sent(const DutInput& input) override;
  void Received(const rig::TimedCanFrame& frame) override;
  void Asked(std::uint64_t tick, std::int64_t now_ns, std::optional<std::int64_t> wall_ns) override;
  void Answered(std::uint64_t tick, std::int64_t now_ns, const ActuatorMessage& command,
                std::optional<std::int64_t> wall_ns) override;

 private:
  explicit DutTrafficLog(RunLogWriter& log) : log_(log) {}
  // The channel of `topic`, added on first use; nullopt when the log could not add it (the log
  // keeps the failure).
  std::optional<std::uint16_t> Channel(std::optional<std::uint16_t>& id,
                                       const google::protobuf::Descriptor& message,
                                       const std::string& topic);

  RunLogWriter& log_;
  std::array<std::optional<std::uint16_t>, kDutInputStreams> input_channels_;
  std::optional<std::uint16_t> can_channel_, step_channel_, command_channel_;
  TrafficBuffer buffer_;
};

}  // namespace hilrig::host
