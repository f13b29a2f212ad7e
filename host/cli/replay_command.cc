#include "host/cli/replay_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "host/cache/setup_caches.h"
#include "host/cli/cli.h"
#include "host/cli/command_help.h"
#include "host/cli/run_command.h"
#include "host/replay/replay_run.h"
#include "host/report/report_files.h"
#include "proto/replay.pb.h"
#include "rig/command_args.h"
#include "rig/number_text.h"

namespace hilrig::host {

const char kReplayUsage[] =
    "  hilrig replay RUN_DIR|RUN.mcap [--set PATH=VALUE,...] [--tolerance T] [--out DIR]\n"
    "      drive a DUT with the inputs, CAN frames and steps a run recorded in its run.mcap,\n"
    "      open loop, and compare its commands with the recorded ones output by output;\n"
    "      exit 1 when one parts by more than T (default 1e-9) or the DUT fails a step\n"
    "      --dut KIND and its options as for run (default: dut_fw in this process, built\n"
    "      from the recorded spec; --set changes that spec first: a gain, a filter length)\n"
    "      --out DIR writes DIR/replay.json; --reference-cache DIR reads the calibrations\n"
    "      where the run kept them (as for run)\n";

namespace {

namespace fs = std::filesystem;

struct ReplayOptions {
  ReplayRequest request;
  std::optional<std::string> out_dir;
  std::optional<std::string> cache_dir;  // --reference-cache: where runs keep calibrations
};

rig::Result<ReplayOptions> ParseReplayOptions(std::vector<std::string> args, const CliStreams& io) {
  auto parsed = ParseCliArgs(args,
                             {"--dut", "--dut-timeout-s", "--dut-link", "--can", "--target-image",
                              "--set", "--tolerance", "--out", "--reference-cache"},
                             {});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (cli.positional.size() != 1) return rig::MakeError("replay takes one run folder or MCAP file");
  ReplayOptions options;
  options.request.log_path = cli.positional.front();
  if (const std::string* sets = cli.Option("--set")) {
    auto overrides = ParseSetOption(*sets);
    if (!overrides) return overrides.error();
    options.request.overrides = std::move(overrides).value();
  }
  if (const std::string* tolerance = cli.Option("--tolerance")) {
    auto value = rig::ParseNumber<double>(*tolerance, "--tolerance");
    if (!value) return value.error();
    if (!(value.value() >= 0) || !std::isfinite(value.value())) {
      return rig::MakeError("--tolerance takes a finite number >= 0, not " + *tolerance);
    }
    options.request.tolerance = value.value();
  }
  if (const std::string* out = cli.Option("--out")) options.out_dir = *out;
  if (const std::string* cache = cli.Option("--reference-cache")) options.cache_dir = *cache;
  auto dut = ParseDutOptions(cli, /*realtime=*/false, io);
  if (!dut) return dut.error();
  options.request.dut_factory = std::move(dut).value();
  return options;
}

std::string TickText(std::uint64_t tick, std::int64_t time_ns) {
  return "tick " + std::to_string(tick) + " (" + rig::NumberText(time_ns / 1e9) + " s)";
}

proto::ReplayReport ReportOf(const ReplayRun& run) {
  const ReplayOutcome& outcome = run.outcome;
  proto::ReplayReport report;
  report.set_log_file(run.log_file);
  report.set_scenario(run.scenario);
  report.set_dut(run.dut);
  report.set_tolerance(outcome.tolerance);
  report.set_verdict(outcome.differs()     ? proto::REPLAY_DIFFERS
                     : outcome.interrupted ? proto::REPLAY_INCOMPLETE
                                           : proto::REPLAY_SAME);
  if (const OutputComparison* first = outcome.FirstParted()) {
    report.set_first_parted(DutOutputName(first->output));
  }
  report.set_inputs(outcome.inputs);
  report.set_can_frames(outcome.can_frames);
  report.set_steps(outcome.steps);
  report.set_commands_compared(outcome.commands_compared);
  report.set_commands_unmatched(outcome.commands_unmatched);
  report.set_log_truncated(run.truncated);
  report.set_recorded_realtime(run.recorded_realtime);
  if (outcome.dut_failure) {
    report.set_dut_failure(outcome.dut_failure->message);
    report.set_dut_failure_tick(outcome.dut_failure_tick);
  }
  for (const OutputComparison& output : outcome.outputs) {
    proto::ReplayOutputDifference* difference = report.add_outputs();
    difference->set_output(DutOutputName(output.output));
    difference->set_largest(output.largest);
    difference->set_largest_tick(output.largest_tick);
    difference->set_largest_time_s(output.largest_time_ns / 1e9);
    difference->set_parted(output.first_past_tick.has_value());
    difference->set_first_past_tick(output.first_past_tick.value_or(0));
    difference->set_first_past_time_s(output.first_past_time_ns / 1e9);
  }
  return report;
}

void PrintReplay(const ReplayRun& run, const CliStreams& io) {
  const ReplayOutcome& outcome = run.outcome;
  io.out << run.scenario << ": replayed " << outcome.steps << " steps of " << run.log_file << " on "
         << run.dut << " (" << outcome.inputs << " inputs, " << outcome.can_frames
         << " CAN frames), " << outcome.commands_compared << " commands compared\n";
  if (run.truncated) io.out << "  the log was cut short: replayed up to its last complete chunk\n";
  if (run.recorded_realtime) {
    io.out << "  recorded in real time: each step replayed with the inputs sent before it\n";
  }
  if (outcome.commands_unmatched > 0) {
    io.out << "  " << outcome.commands_unmatched << " recorded commands had no replayed step\n";
  }
  for (const OutputComparison& output : outcome.outputs) {
    char name[32];
    std::snprintf(name, sizeof(name), "%-24s", DutOutputName(output.output));
    io.out << "  " << name << " largest " << rig::NumberText(output.largest);
    if (output.largest > 0)
      io.out << " at " << TickText(output.largest_tick, output.largest_time_ns);
    if (output.first_past_tick) {
      io.out << ", first past " << rig::NumberText(outcome.tolerance) << " at "
             << TickText(*output.first_past_tick, output.first_past_time_ns);
    }
    io.out << "\n";
  }
  if (outcome.dut_failure) {
    io.out << "DIFFERS: the DUT failed at tick " << outcome.dut_failure_tick << ": "
           << outcome.dut_failure->message << "\n";
  } else if (const OutputComparison* first = outcome.FirstParted()) {
    io.out << "DIFFERS: " << DutOutputName(first->output) << " parts first, at "
           << TickText(*first->first_past_tick, first->first_past_time_ns) << "\n";
  } else if (outcome.interrupted) {
    io.out << "INTERRUPTED at " << rig::NumberText(outcome.replayed_to_ns / 1e9)
           << " s: no output parted by more than " << rig::NumberText(outcome.tolerance)
           << " so far\n";
  } else {
    io.out << "SAME: no output parted by more than " << rig::NumberText(outcome.tolerance) << "\n";
  }
}

}  // namespace

int ReplayCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseReplayOptions(args, io);
  if (!options) {
    io.err << "hilrig replay: " << options.error().message << "\n" << HelpPointer("replay");
    return kExitBadInput;
  }
  ReplayRequest& request = options.value().request;
  // The calibrations and field maps the runs keep, where `hilrig run --reference-cache` keeps them.
  const SetupCaches caches = MakeSetupCaches(options.value().cache_dir, io.err);
  request.film_models = caches.film_models.get();
  request.calibrations = caches.calibrations.get();
  const std::optional<std::string>& out_dir = options.value().out_dir;
  if (out_dir) {
    std::error_code error;
    fs::create_directories(*out_dir, error);
    if (error) {
      io.err << "hilrig replay: cannot make " << *out_dir << ": " << error.message() << "\n";
      return kExitBadInput;
    }
    request.run_folder = *out_dir;
  }
  std::variant<ReplayRun, ReplayError> replayed = ReplayRecordedRun(request, io.stop_requested);
  if (const ReplayError* error = std::get_if<ReplayError>(&replayed)) {
    io.err << "hilrig replay: " << error->message << "\n";
    return kExitBadInput;
  }
  const ReplayRun& run = std::get<ReplayRun>(replayed);
  PrintReplay(run, io);
  if (out_dir) {
    const std::string path = (fs::path(*out_dir) / "replay.json").string();
    if (auto written = WriteJsonFile(ReportOf(run), path); !written) {
      io.err << "hilrig replay: " << written.error().message << "\n";
      return kExitBadInput;
    }
  }
  return run.outcome.differs() || run.outcome.interrupted ? kExitCheckFailed : kExitPass;
}

}  // namespace hilrig::host
