// Another process on the host attacks a lockstep run with the DUT in its own process: it connects
// to the runner's link port before dut_emu does, or sends a CAN frame to dut_emu's UDP CAN port
// (tests/host/linked_dut/link_intruder.cc). Either way the run must be the one the in-process DUT
// gives, byte for byte, with the intrusion counted in the report.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "host/dut/firmware_config.h"
#include "host/linked_dut/process_dut.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "rig/clock.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

struct RunOutput {
  std::string trace_csv;
  proto::Report report;
};

// The hover scene, cut to 3 s: long enough for the intruder to act while the DUT runs.
RunOutput RunHover(const DutFactory& dut_factory) {
  const auto spec =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt,
                                          ::hilrig::test_support::SourceDir() + "/scenarios");
  config.duration_s = 3;
  EXPECT_TRUE(LoadTactileCalibration(config).ok());
  std::ostringstream trace;
  RunSinks sinks;
  sinks.trace_csv = &trace;
  const rig::SteadyClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.dut_factory = dut_factory;
  RunOutput run;
  run.report = RunScenario(config, sinks, control);
  run.trace_csv = trace.str();
  return run;
}

// dut_emu behind link_intruder, which attacks the run in `mode` ("hello" or "datagram").
DutFactory IntrudedProcessDut(const std::string& mode) {
  return [mode](const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
                double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    ProcessDutOptions options;
    options.transport = DutLinkTransport::kTcp;  // the port an intruder can reach
    options.dut_emu_path = ::hilrig::test_support::BinDir() + "/link_intruder";
    options.extra_args = {"--intrude", mode};
    options.start_timeout_s = 3;
    return std::unique_ptr<DutPort>(std::make_unique<ProcessDut>(
        FirmwareFor(config), std::move(bus), control_period_s, options));
  };
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::string DutDescription(const proto::Report& report) {
  for (const auto& model : report.models()) {
    if (model.name() == "dut") return model.fidelity();
  }
  return "";
}

TEST(ProcessDutIntruderTest, PeerThatConnectsFirstIsNotTakenForTheDut) {
  const RunOutput in_process = RunHover({});
  const RunOutput attacked = RunHover(IntrudedProcessDut("hello"));
  ASSERT_EQ(in_process.report.stop_reason(), "completed");
  EXPECT_EQ(attacked.report.stop_reason(), "completed");
  ASSERT_GT(in_process.trace_csv.size(), 10'000u);
  EXPECT_TRUE(attacked.trace_csv == in_process.trace_csv) << "trace.csv differs";
  EXPECT_EQ(Metric(attacked.report, "link_peers_refused"), 1.0);
  EXPECT_EQ(Metric(attacked.report, "link_commands_received"),
            static_cast<double>(attacked.report.ticks()));
  EXPECT_NE(DutDescription(attacked.report).find("1 link peer refused: 127.0.0.1:"),
            std::string::npos)
      << DutDescription(attacked.report);
  EXPECT_NE(DutDescription(attacked.report).find("(no_token)"), std::string::npos)
      << DutDescription(attacked.report);
}

TEST(ProcessDutIntruderTest, ForgedFrameOnTheDutsCanPortIsDroppedAndCounted) {
  const RunOutput in_process = RunHover({});
  const RunOutput attacked = RunHover(IntrudedProcessDut("datagram"));
  ASSERT_EQ(in_process.report.stop_reason(), "completed");
  EXPECT_EQ(attacked.report.stop_reason(), "completed");
  EXPECT_TRUE(attacked.trace_csv == in_process.trace_csv) << "trace.csv differs";
  EXPECT_EQ(Metric(attacked.report, "dut_can_frames_dropped_foreign"), 1.0);
  // The intruder held a silent connection to the link port until the DUT proved itself.
  EXPECT_EQ(Metric(attacked.report, "link_peers_refused"), 1.0);
  EXPECT_NE(DutDescription(attacked.report).find("(silent)"), std::string::npos)
      << DutDescription(attacked.report);
}

// Datagrams that are no frame at all are dropped by the DUT's bus, and the report says how many:
// a flood on the DUT's CAN port never passes unseen.
TEST(ProcessDutIntruderTest, GarbageDatagramsOnTheDutsCanPortAreCountedInTheReport) {
  const RunOutput in_process = RunHover({});
  const RunOutput attacked = RunHover(IntrudedProcessDut("garbage"));
  EXPECT_EQ(attacked.report.stop_reason(), "completed");
  EXPECT_TRUE(attacked.trace_csv == in_process.trace_csv) << "trace.csv differs";
  EXPECT_EQ(Metric(attacked.report, "dut_can_frames_dropped_malformed"), 100.0);
  EXPECT_EQ(Metric(attacked.report, "dut_can_frames_dropped_foreign"), 0.0);
  EXPECT_EQ(Metric(attacked.report, "link_can_frames_dropped_malformed"), 0.0);
}

}  // namespace
}  // namespace hilrig::host
