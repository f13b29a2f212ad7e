// The runner: owns the simulated clock, the plant, the sensor emulators, the CAN bus and the DUT
// port, and steps them in a fixed order each physics tick. In lockstep (the default) there is no
// wall-clock sync (the wall clock is only read to report the real-time factor) and the DUT answers
// each control tick before the plant moves on. In real time (RunControl::realtime_clock) each tick
// waits until it is due on that clock, the plant never waits for the DUT (it holds the last command
// until a newer one arrives) and the report gets the loop's timing figures and timing verdicts.
// The tick is one piece of code in both modes: how it gets the DUT's command is a CommandExchange
// (host/runner/command_exchange.h), and real-time pacing wraps the tick from outside.
// Envelope checks read the trace as it is produced and may abort the run; the trace and the CAN log
// stream out as the run goes, so an interrupted run still leaves them behind.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/dut/dut_traffic.h"
#include "host/runner/device_emulator.h"
#include "host/scenario/scenario_config.h"
#include "host/trace/trace_sample.h"
#include "proto/report.pb.h"
#include "rig/can_bus.h"
#include "rig/clock.h"

namespace hilrig::host {

struct RunSinks {
  std::ostream* trace_csv = nullptr;  // optional
  std::ostream* can_log = nullptr;    // optional, candump -l format
  std::ostream* progress = nullptr;   // optional, a line every few wall seconds on long runs
  // Optional: every trace row as it is recorded (the run's plots, a bench's error comparison).
  std::function<void(const TraceSample&)> trace_sample = {};
  // Optional: called with the simulated time reached each time the trace and CAN log have been
  // flushed (every few wall seconds), so the run's folder can say how far a run that never
  // finishes got.
  std::function<void(double simulated_s)> flushed = {};
};

struct RunControl {
  const rig::Clock* wall_clock = nullptr;             // required; only for timing the run
  const std::atomic<bool>* stop_requested = nullptr;  // optional, e.g. set by SIGINT
  DutFactory dut_factory = {};                        // optional; default in-process
  // Set: pace the run in real time on this clock (usually the same SteadyClock as wall_clock);
  // null: lockstep.
  const rig::PacingClock* realtime_clock = nullptr;
  // Devices ticked after the scene's own (host/runner/scene_devices.h), in this order; not owned,
  // they must outlive the run.
  std::vector<DeviceEmulator*> added_devices = {};
  // The run's output folder, handed to the DUT before it starts (DutPort::SetRunFolder); empty:
  // the run writes no files of its own.
  std::string run_folder = {};
  // Optional: every input, CAN frame, step and command between the runner and the DUT, as they
  // are exchanged (the run's log, for a replay); must outlive the run.
  DutTrafficSink* dut_traffic = nullptr;
};

// A run that can be stepped tick by tick (benchmarks, tests); RunScenario() drives one to its end.
class ScenarioRunner {
 public:
  // `config` must outlive the runner.
  ScenarioRunner(const ScenarioConfig& config, const RunSinks& sinks, const RunControl& control);
  ~ScenarioRunner();
  ScenarioRunner(const ScenarioRunner&) = delete;
  ScenarioRunner& operator=(const ScenarioRunner&) = delete;

  // Advances one physics tick; false once the run has ended (its duration reached, an aborting
  // envelope violated, the DUT failed, or a stop requested). Tick() after the end does nothing.
  bool Tick();

  // Ends the run and builds its report; call once.
  proto::Report Finish();

  // Timeline entries and schedule pieces the run has stepped over so far (setpoints aside, which
  // are looked up in O(log n)): each at most once over a run, so a tick's share does not grow with
  // the timeline.
  std::uint64_t timeline_entries_stepped() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Runs the scenario to its end (or to an abort) and returns the report.
proto::Report RunScenario(const ScenarioConfig& config, const RunSinks& sinks,
                          const RunControl& control);

}  // namespace hilrig::host
