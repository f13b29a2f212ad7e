#include "host/replay/replay_run.h"

#include <filesystem>
#include <memory>

#include "host/cache/setup_caches.h"
#include "host/dut/in_process_dut.h"
#include "host/report/run_log.h"
#include "host/scenario/checked_resolve.h"
#include "host/scenario/field_path.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

ReplayError Failed(ReplayFailure failure, std::string message) {
  return {failure, std::move(message)};
}

// The log file of `path`: a folder's run.mcap, else the path itself.
std::string LogFileOf(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) return (fs::path(path) / kRunLogFile).string();
  return path;
}

std::string McapErrorText(const mcap::McapError& error) {
  return error.detail + " (at byte " + std::to_string(error.offset) + ")";
}

// The recorded spec with `overrides` set, resolved and its DUT's calibration made.
rig::Result<ScenarioConfig> ConfigOf(const proto::RunRecording& recording,
                                     const ReplayRequest& request,
                                     const std::atomic<bool>* stop_requested, bool& bad_spec) {
  proto::Scenario spec = recording.spec();
  bad_spec = true;
  for (const auto& [path, value] : request.overrides) {
    auto set = SetNumberAt(spec, path, value);
    if (!set.ok()) return rig::InContext(spec.name() + ": --set ", set.error());
  }
  auto config = ResolveChecked(spec, recording.spec_directory(), recording.seed());
  if (!config) return config.error();
  bad_spec = false;
  if (auto set_up = SetUpTactile(spec, config.value(), request.film_models, request.calibrations,
                                 stop_requested);
      !set_up) {
    return set_up.error();
  }
  return config;
}

}  // namespace

std::variant<ReplayRun, ReplayError> ReplayRecordedRun(const ReplayRequest& request,
                                                       const std::atomic<bool>* stop_requested) {
  ReplayRun run;
  run.log_file = LogFileOf(request.log_path);
  mcap::McapReadResult read = mcap::ReadMcapFile(run.log_file, /*recover=*/true);
  if (!read.ok()) {
    // A file that cannot be opened says so with its path; the others are told where they fail.
    return Failed(ReplayFailure::kBadLog, read.error->kind == mcap::McapErrorKind::kUnreadableFile
                                              ? read.error->detail
                                              : run.log_file + ": " + McapErrorText(*read.error));
  }
  run.truncated = read.contents.truncated;
  auto traffic = RecordedTraffic::Of(read.contents);
  if (!traffic)
    return Failed(ReplayFailure::kBadLog, run.log_file + ": " + traffic.error().message);
  const proto::RunRecording& recording = traffic.value().recording();
  run.scenario = recording.spec().name();
  run.recorded_realtime = recording.realtime();

  bool bad_spec = false;
  auto config = ConfigOf(recording, request, stop_requested, bad_spec);
  if (!config) {
    return Failed(bad_spec ? ReplayFailure::kBadSpec : ReplayFailure::kSetUp,
                  config.error().message);
  }
  auto owned_bus = std::make_unique<ReplayCanBus>();
  ReplayCanBus& bus = *owned_bus;
  auto made = MakeDut(request.dut_factory, config.value(), std::move(owned_bus));
  if (!made) return Failed(ReplayFailure::kSetUp, "the DUT: " + made.error().message);
  std::unique_ptr<DutPort> dut = std::move(made).value();
  dut->SetRunFolder(request.run_folder);
  if (auto started = dut->Start(); !started) {
    dut->Stop();
    return Failed(ReplayFailure::kSetUp, "the DUT did not start: " + started.error().message);
  }
  run.dut = dut->description();
  auto outcome =
      ReplayTraffic(read.contents, traffic.value(), *dut, bus, request.tolerance, stop_requested);
  dut->Stop();
  if (!outcome)
    return Failed(ReplayFailure::kBadLog, run.log_file + ": " + outcome.error().message);
  run.outcome = std::move(outcome).value();
  return run;
}

}  // namespace hilrig::host
