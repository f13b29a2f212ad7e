// The transport half of a DUT behind a link: what carries a tick's request to the DUT and its
// answers back, once per kind of link (the process link over shared memory or TCP, a serial line;
// a MAVLink peer would be one more). The session around it (start and stop, the request ledger
// and the watchdog, lockstep waiting or real-time polling, the first failure that sticks, the
// process behind the link) is LinkedDut's (host/linked_dut/linked_dut.h), written once, so a link
// only encodes, moves and decodes. host/linked_dut/fake_dut_link.h is a scripted one for tests. A
// link is used from one thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/link/hil_messages.h"
#include "proto/hil_link.pb.h"
#include "rig/can_frame.h"
#include "rig/clock.h"
#include "rig/metric.h"
#include "rig/result.h"

namespace hilrig::host {

// One control tick's request, as the session hands it to the link.
struct LinkRequest {
  std::uint64_t tick = 0;
  std::int64_t now_ns = 0;  // the rig's time of the tick
  // The CAN frames that reached the runner's "dut" endpoint since the last request.
  const std::vector<rig::TimedCanFrame>* frames = nullptr;
  bool realtime = false;
  std::int64_t sent_wall_ns = 0;  // the session's clock when sent (0 in lockstep)
};

// What the link read next from the DUT.
enum class DutLinkEventKind {
  kNothing,  // nothing complete within the wait
  kAnswer,   // a command answering `answers_tick`; TakeAnswer gives it once the session took it
  kIgnored,  // something the link counted and set aside (a stray message on a line)
  kClosed,   // the link is gone (closed, or its transport failed): `error` says how
  kFailed,   // the DUT broke the protocol or said goodbye: `error` says how
};

struct DutLinkEvent {
  DutLinkEventKind kind = DutLinkEventKind::kNothing;
  std::uint64_t answers_tick = 0;   // kAnswer
  std::optional<rig::Error> error;  // kClosed, kFailed
};

class DutLink {
 public:
  virtual ~DutLink() = default;

  // Opens the transport and shakes hands (hello, the firmware configuration), on `clock` where it
  // waits. Fails with what the DUT, the transport or the process behind it did wrong.
  virtual rig::Result<void> Open(const rig::Clock& clock) = 0;
  // The folder the run's files go to, before Open; a link that logs its traffic writes there.
  virtual void SetRunFolder(const std::string& folder) { (void)folder; }
  // Hands over one input; a link may hold it to go out with the next request. Fails when the link
  // cannot take it; rig::ErrorCode::kLinkClosed means the link is gone.
  virtual rig::Result<void> Input(const DutInput& input, bool realtime,
                                  std::int64_t sent_wall_ns) = 0;
  // Sends the tick's request, with the held inputs and the frames; fails as Input does.
  virtual rig::Result<void> Request(const LinkRequest& request) = 0;
  // A lossy link's retry: the last request again, once no answer came within this; nullopt for a
  // link that never loses one. An answer to a tick already answered is then a twin, not a fault.
  virtual std::optional<std::int64_t> resend_after_ns() const { return std::nullopt; }
  virtual rig::Result<void> Resend() { return {}; }
  // The next thing the DUT sent, waiting at most `timeout_ms` (0: not at all).
  virtual DutLinkEvent Receive(int timeout_ms) = 0;
  // The command of the kAnswer just received, now that the session matched it to its request;
  // the link keeps what the command reports (the DUT's counters, its work, latencies measured at
  // `arrival_wall_ns`). Fails on a command that does not decode.
  virtual rig::Result<ActuatorMessage> TakeAnswer(std::int64_t arrival_wall_ns) = 0;

  // Whether a process of the rig's runs behind the link (dut_emu, an emulator), and how it ended
  // ("dut process exited with status 3"): nullopt while it runs, or without one.
  virtual bool has_peer() const = 0;
  virtual std::optional<std::string> PeerExit() = 0;
  // Ends the link: a goodbye when `goodbye` (the run did not fail), then the process behind it is
  // ended and reaped. Safe on a link that never opened.
  virtual void Close(bool goodbye) = 0;

  virtual std::string description() const = 0;
  // Added to the session's "did not answer tick T within S" (the retries so far).
  virtual std::string timeout_detail() const { return {}; }
  // Prefix of the session's counters in the report ("link_", "line_").
  virtual std::string metric_prefix() const = 0;
  // The link's own figures; `realtime` adds those only real-time pacing has.
  virtual std::vector<rig::Metric> metrics(bool realtime) const = 0;
  // Response latencies per input stream, measured in real time; none when the link cannot tell.
  virtual std::vector<StreamLatency> input_latencies() const { return {}; }
  virtual std::optional<TargetSummary> target() const { return std::nullopt; }
  // Sensor bytes the DUT reported stepping without (DutCounters::sensor_bytes_missing).
  virtual std::uint64_t sensor_bytes_missing() const { return 0; }
  // The DUT's front-end counts as it last reported them, over a link that carries them; nullopt
  // when the DUT reports none.
  virtual std::optional<proto::DutFrontEndCounters> front_end_counters() const {
    return std::nullopt;
  }
};

}  // namespace hilrig::host
