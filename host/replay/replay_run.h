// `hilrig replay`'s work without its command line: a run's log read (a folder's run.mcap or the
// file itself; a log cut short is read up to its last complete chunk), the run's DUT rebuilt from
// the recorded spec (with the replay's --set overrides, its calibration through the setup
// caches) or the DUT a factory makes, and the recorded traffic replayed on it
// (host/replay/replay.h).
#pragma once

#include <atomic>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "host/cache/calibration_store.h"
#include "host/dut/dut_port.h"
#include "host/replay/replay.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "rig/result.h"

namespace hilrig::host {

// Bit for bit is what the same build gives; a DUT that computes in another precision or order (a
// firmware image) is given a wider tolerance on the command line.
inline constexpr double kDefaultReplayTolerance = 1e-9;

struct ReplayRequest {
  std::string log_path;  // a run folder or an MCAP file
  // Numbers of the recorded spec set by field path (`--set`), before the DUT is built.
  std::vector<std::pair<std::string, double>> overrides;
  DutFactory dut_factory;  // unset: dut_fw in this process
  double tolerance = kDefaultReplayTolerance;
  FilmFieldModels* film_models = nullptr;
  const FileCalibrationStore* calibrations = nullptr;
  std::string run_folder;  // handed to the DUT (a DUT process's link log); empty: none
};

struct ReplayRun {
  std::string log_file;  // the MCAP file read
  std::string scenario;  // the recorded spec's name
  std::string dut;       // the replayed DUT, as it describes itself
  bool recorded_realtime = false;
  bool truncated = false;  // the log was cut short; its complete chunks were replayed
  ReplayOutcome outcome;
};

enum class ReplayFailure {
  kBadLog,   // unreadable, not a run's log, or a message that does not decode
  kBadSpec,  // the recorded spec with the overrides is not valid
  kSetUp,    // the DUT's calibration could not be made, or the DUT did not start
};

struct ReplayError {
  ReplayFailure failure;
  std::string message;
};

// Fails before the first step, or on a message of the log that does not decode.
std::variant<ReplayRun, ReplayError> ReplayRecordedRun(const ReplayRequest& request,
                                                       const std::atomic<bool>* stop_requested);

}  // namespace hilrig::host
