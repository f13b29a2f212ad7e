// A run's MCAP log (run.mcap beside report.json): the trace as channels a reader such as Foxglove
// or @mcap/core opens without the rig, each a protobuf message of proto/run_log.proto with its
// descriptors stored in the file (host/mcap/protobuf_channel.h). One message per channel per
// trace sample, at the sample's simulated time from a fixed epoch (kRunLogEpochNs, as can.log):
// /plant/vehicle (pose, velocity, thrusts, reference), /dut/estimates, and in grasp scenes
// /plant/grasp; with the pads, /plant/pads and /dut/pads; the timeline's events on /run/events
// as the trace passes them. For Foxglove's 3D panel, in Foxglove's own schemas (proto/foxglove/):
// the vehicle's pose as the transform world -> body on /tf per sample, and the reference
// trajectory once at time 0 on /plant/reference_path. Each envelope of the scene on
// /checks/<name>: what its check reads per sample, its bounds and its margin. Written as the run
// goes through McapWriter's bounded chunks.
#pragma once

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message_lite.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/checks/envelope_check.h"
#include "host/mcap/mcap_writer.h"
#include "host/report/svg_plot.h"
#include "host/trace/log_epoch.h"
#include "host/trace/trace_sample.h"
#include "rig/result.h"

namespace hilrig::host {

inline constexpr const char* kRunLogFile = "run.mcap";

// The frames of /tf: the world's (z up, as the plant's) and the vehicle's body.
inline constexpr const char* kRunLogWorldFrame = "world";
inline constexpr const char* kRunLogBodyFrame = "body";

// A pose of the reference trajectory: where it asks the vehicle to be, and its heading.
struct ReferencePose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
};

// What a run's log carries besides its trace.
struct RunLogScene {
  bool grasp = false;              // an object: /plant/grasp
  bool pads = false;               // the tactile pads: /plant/pads and /dut/pads
  std::vector<PlotMarker> events;  // the timeline's, in time order, as the plots mark them
  // The reference over the run, in time order, for /plant/reference_path (none: no channel).
  std::vector<ReferencePose> reference_path;
  // The scenario's envelopes, each read by a check of its own as the runner's checks read them.
  std::vector<EnvelopeSpec> envelopes;
};

// The rotation of roll, pitch and yaw (rad) applied as the trace's roll_pitch_yaw_deg has them:
// yaw about z, then pitch about the new y, then roll about the newest x (Rz * Ry * Rx).
Eigen::Quaterniond QuaternionOfRollPitchYaw(const Eigen::Vector3d& roll_pitch_yaw_rad);

class RunLogWriter {
 public:
  // Writes the header, schemas and channels to `out`, which must outlive the writer. Fails when
  // the stream does.
  static rig::Result<std::unique_ptr<RunLogWriter>> Open(std::ostream& out, RunLogScene scene);

  // Logs one trace sample, and the events up to its time first. A failure (the stream, the
  // compressor) sticks: later samples are dropped and Close reports it. Allocates only when a
  // chunk is full.
  void Add(const TraceSample& sample);

  // The last chunk and the summary. Fails with the first failure of the run.
  rig::Result<void> Close();

  // For the run's other writers (the DUT's traffic, ...): a channel of protobuf messages of type
  // `message` on `topic`, its schema (the descriptor's file and imports) stored once per type.
  // Fails when the stream does, and the failure sticks as Add's do.
  rig::Result<std::uint16_t> AddChannel(const google::protobuf::Descriptor& message,
                                        std::string_view topic);
  // Logs `message` on `channel` at simulated time `time_ns` (from 0, the run's start) and
  // `publish_time_ns` (the same when unset). Fails as Add does.
  void Log(std::uint16_t channel, std::int64_t time_ns,
           const google::protobuf::MessageLite& message,
           std::optional<std::int64_t> publish_time_ns = std::nullopt);
  // The same with the message already in wire bytes (written without protobuf objects).
  void LogBytes(std::uint16_t channel, std::int64_t time_ns, std::span<const std::uint8_t> payload,
                std::optional<std::int64_t> publish_time_ns = std::nullopt);

 private:
  struct Channels {
    std::uint16_t vehicle = 0, estimates = 0, grasp = 0, plant_pads = 0, dut_pads = 0, events = 0,
                  tf = 0, reference_path = 0;
  };
  // An envelope's channel and its own check: the log reads each sample as the runner's check does,
  // without reaching into the runner.
  struct LoggedEnvelope {
    EnvelopeCheck check;
    EnvelopeProgress progress;
    std::uint16_t channel = 0;
  };
  RunLogWriter(std::ostream& out, RunLogScene scene);
  void Write(std::uint16_t channel, std::int64_t log_time_ns, std::string_view payload,
             std::int64_t publish_time_ns);
  // `message` serialized into payload_ and written; the publish time is the log time unless given.
  void WriteMessage(std::uint16_t channel, std::int64_t log_time_ns,
                    const google::protobuf::MessageLite& message, std::int64_t publish_time_ns);
  void WriteMessage(std::uint16_t channel, std::int64_t log_time_ns,
                    const google::protobuf::MessageLite& message) {
    WriteMessage(channel, log_time_ns, message, log_time_ns);
  }
  void WriteEventsUpTo(double time_s);
  void WriteReferencePath();
  void WriteEnvelopes(const TraceSample& sample, std::int64_t log_time_ns);

  mcap::McapWriter writer_;
  RunLogScene scene_;
  Channels channels_;
  std::vector<LoggedEnvelope> envelopes_;
  std::map<const google::protobuf::Descriptor*, std::uint16_t> schemas_;  // one per message type
  std::size_t next_event_ = 0;
  std::uint32_t sequence_ = 0;
  std::string payload_;  // reused: a sample's messages are serialized into it one by one
  std::optional<rig::Error> failure_;
};

}  // namespace hilrig::host
