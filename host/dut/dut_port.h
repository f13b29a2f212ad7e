// The seam between the runner and the device under test. The runner pushes sensor messages and the
// setpoint as they happen, then asks the DUT for its command at each control tick; in lockstep the
// DUT answers before the plant moves on. An in-process DUT, a DUT process over the HIL link and
// real hardware all sit behind this interface; the runner cannot tell them apart. Tactile and
// reference magnetometer samples do not pass here: they travel as CAN frames on the bus.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/link/hil_messages.h"
#include "rig/duration_histogram.h"
#include "rig/metric.h"
#include "rig/result.h"

namespace hilrig::rig {
class CanBus;  // rig/can_bus.h
}  // namespace hilrig::rig

namespace hilrig::host {

struct ScenarioConfig;  // host/scenario/scenario_config.h

// What went to a DUT and what its front end made of it. The IMU, VIO and CAN counts are the
// rig's: what it handed the DUT (for a DUT behind a link, what it sent or forwarded on the link).
// The front end's counts (rejected frames, samples, gaps, losses, flagged samples) are the DUT's
// own and mean something only when `front_end_counted`: the in-process dut_fw and dut_emu count
// them, a board's firmware and a flight stack do not report them.
struct DutCounters {
  std::uint64_t imu_messages = 0;
  std::uint64_t vio_messages = 0;
  std::uint64_t can_frames_received = 0;
  bool front_end_counted = false;
  std::uint64_t can_frames_rejected = 0;  // frames that did not decode (wrong DLC, unknown id)
  std::uint64_t sensor_samples = 0;       // Hall sensor node samples, all seven nodes
  std::uint64_t sensor_sequence_gaps = 0;
  std::uint64_t sensor_samples_lost = 0;
  // Tactile samples the front end could not turn into force (saturated, singular S(B), stale
  // reference, ...), summed over the six pads.
  std::uint64_t tactile_samples_flagged = 0;
  // Sensor bytes the runner sent a DUT on a board for a lockstep step that the board stepped
  // without (they came late or never): such a run's trace is not the lockstep trace. Only a DUT
  // that receives its sensor samples over a line of its own can count them.
  std::uint64_t sensor_bytes_missing = 0;

  // Counts one input sent to the DUT; the report counts the IMU and VIO streams only.
  void Count(const DutInput& input) {
    imu_messages += std::holds_alternative<ImuMessage>(input) ? 1 : 0;
    vio_messages += std::holds_alternative<VioMessage>(input) ? 1 : 0;
  }
};

// How a run asks a DUT for its commands: Step and wait (lockstep), or RequestStep and PollCommand
// while the plant goes on (real time). A DUT behind a link is told which when it is built, since
// the two send and wait differently.
enum class DutPacing { kLockstep, kRealtime };

// How long the DUT took to respond to one input stream ("imu", "vio", "setpoint", "can"): from the
// runner sending a message to the first command that reflects it, in wall time (real-time runs).
struct StreamLatency {
  std::string stream;
  rig::DurationSummary latency;
};

// A DUT on a target of its own (a board, an emulated MCU): the target as it described itself and
// the work per control step it measured, in its cycle counter (core cycles at core_clock_hz).
struct TargetSummary {
  std::string board;
  std::uint32_t core_clock_hz = 0;
  std::uint32_t flash_used_bytes = 0;
  std::uint32_t ram_used_bytes = 0;
  std::uint32_t stack_bytes = 0;
  std::uint64_t steps_measured = 0;
  std::uint32_t work_p50_cycles = 0;
  std::uint32_t work_p99_cycles = 0;
  std::uint32_t work_max_cycles = 0;
  // QEMU under -icount: the counts are SysTick at core_clock_hz of virtual time in which every
  // instruction takes 1 ns, so one count is 1e9 / core_clock_hz instructions.
  bool emulated_core = false;
};

// Lifecycle: the runner calls Start once before anything else; a DUT that fails to start is
// never sent a message nor stepped. Stop comes once at the end of every run, a failed start
// included, so a DUT can release what a half-done start left behind.
class DutPort {
 public:
  virtual ~DutPort() = default;

  // Brings the DUT up (an in-process DUT has nothing to do; a DUT process is spawned and shakes
  // hands on its link); an error says why it cannot run.
  virtual rig::Result<void> Start() { return {}; }
  // The folder the run's files go to (empty: none), before Start: a DUT that logs its link's
  // traffic writes its log there.
  virtual void SetRunFolder(const std::string& folder) { (void)folder; }
  // Ends the DUT's run; after it the DUT is only asked for its counters and metrics.
  virtual void Stop() {}

  // Hands the DUT one sensor message or the setpoint, in the order they happen.
  virtual void Send(const DutInput& input) = 0;
  // Whether the DUT fuses a magnetometer, barometer and GNSS (a flight stack over MAVLink): the
  // runner emulates them only then. The rig's own controller does not.
  virtual bool TakesNavigationSensors() const { return false; }

  // Runs the DUT's control step for control tick `tick` at `now_ns` and returns its command; an
  // error means the DUT did not answer properly (timeout, bad message) and ends the run.
  virtual rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) = 0;

  // Real-time runs, where the plant does not wait for the DUT: RequestStep asks for control tick
  // `tick`'s command without waiting, and PollCommand returns the newest command that has arrived
  // since the last poll (nullopt: none yet), or an error that ends the run (the DUT died, the link
  // broke). The default suits a DUT that answers at once (in process): it runs Step inside
  // RequestStep and hands the answer to the next poll.
  virtual void RequestStep(std::uint64_t tick, std::int64_t now_ns);
  virtual rig::Result<std::optional<ActuatorMessage>> PollCommand();
  // Per-stream response latency measured in real-time runs; a DUT that does not measure has none.
  virtual std::vector<StreamLatency> response_latencies() const { return {}; }

  virtual DutCounters counters() const = 0;
  virtual std::string description() const = 0;

  // The link's figures for the run report, each with its unit (messages and named link errors
  // counted, a target's clock in Hz, its memory in bytes, its work in cycles); a DUT without a
  // link has none.
  virtual std::vector<rig::Metric> link_metrics() const { return {}; }

  // The target the DUT runs on; nullopt for a DUT on the host, or one not started.
  virtual std::optional<TargetSummary> target() const { return std::nullopt; }

 private:
  // The default RequestStep's answer, until PollCommand takes it.
  std::optional<rig::Result<ActuatorMessage>> immediate_answer_;
};

// Builds the DUT the runner talks to, given the scene, the DUT's own endpoint on the emulated CAN
// bus and the control period. Unset: the in-process dut_fw (InProcessDut). MakeDutFactory
// (host/linked_dut/dut_choice.h) makes the one a command line names.
using DutFactory = std::function<rig::Result<std::unique_ptr<DutPort>>(
    const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus, double control_period_s)>;

}  // namespace hilrig::host
