#include "host/cli/cli.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "host/cache/calibration_store.h"
#include "host/cache/field_map_store.h"
#include "host/cache/reference_cache.h"
#include "host/cache/setup_caches.h"
#include "host/cli/bench_command.h"
#include "host/cli/cli_args.h"
#include "host/cli/tactile_commands.h"
#include "host/dut/firmware_config.h"
#include "host/dut/process_dut.h"
#include "host/report/report_files.h"
#include "host/report/run_folder.h"
#include "host/report/run_plots.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/work_precision/work_precision.h"
#include "rig/clock.h"
#include "rig/file_io.h"
#include "rig/folder_lock.h"
#include "rig/realtime_scheduling.h"
#include "rig/stop_request.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage:\n"
    "  hilrig run FILE.textproto [--out DIR] [--seed N]   run one scenario\n"
    "  hilrig run DIR/ [--out DIR] [--seed N]             run every *.textproto in DIR\n"
    "      run options: --dut inproc|process (the DUT in this process, the default, or in\n"
    "      its own dut_emu process over the HIL link, lockstep) [--dut-timeout-s S]\n"
    "      (how long a dut process may take to answer a tick; default 1) [--realtime]\n"
    "      (pace the run by the wall clock, the DUT answering asynchronously; reports loop\n"
    "      period, late ticks and DUT latency and grades the spec's timing envelopes)\n"
    "      [--rt-priority N] (the real-time loop and its dut process run under SCHED_FIFO\n"
    "      at N, 1-99, default 50; 0 keeps the default scheduler; refused: a warning)\n"
    "  hilrig check FILE.textproto...                     validate scenario specs\n"
    "  hilrig bench --out DIR [--scenes a,b|all] [--duration-s S] [--quick]\n"
    "                                                     work-precision sweep\n"
    "  hilrig calibrate --out DIR [--seed N] [--field F]  calibrate the tactile sensors\n"
    "  hilrig accuracy --calibration FILE --out DIR [--seed N] [--field F]\n"
    "                                                     held-out force error\n"
    "  hilrig decode --calibration FILE                   stdin 'bx by bz' (T) -> S\n"
    "  hilrig help                                        this text\n"
    "run writes report.json, junit.xml, trace.csv and can.log into --out (default\n"
    "hilrig_out/<scenario>) and compares the trace with the scene's reference run (tight\n"
    "integrator and field, kept in a cache per build: --reference-cache DIR, default\n"
    "~/.cache/hilrig/reference; DIR/field_maps and DIR/calibrations keep tabulated field maps\n"
    "and calibrations, with or without the reference); --no-reference skips it. Exit codes: 0\n"
    "every check met its expected verdict, 1 a check did not or the run was cut short, 2 bad\n"
    "input or usage.\n";

// SCHED_FIFO priority of a real-time run unless --rt-priority says otherwise: the middle of the
// range, the default of ros2_control's controller manager.
constexpr int kDefaultRealtimePriority = 50;

struct RunOptions {
  std::string target;
  std::optional<std::string> out_dir;
  std::optional<std::uint64_t> seed;
  bool reference = true;  // --no-reference: do not compare with the reference run
  std::optional<std::string> reference_cache_dir;      // --reference-cache
  DutFactory dut_factory;                              // --dut process; unset: in process
  bool realtime = false;                               // --realtime: paced by the wall clock
  int realtime_priority = kDefaultRealtimePriority;    // --rt-priority; 0: default scheduler
  const FieldMapTableStore* field_maps = nullptr;      // tabulated maps kept between runs
  const FileCalibrationStore* calibrations = nullptr;  // calibrations kept between runs
};

using Streams = CliStreams;

// --dut inproc|process and --dut-timeout-s; an unset factory is the in-process DUT. In real time
// the process DUT reads a wall clock of its own for its watchdog and latencies (differences only,
// so its epoch does not matter); the factory keeps it alive for every DUT it starts.
rig::Result<DutFactory> ParseDutOptions(const CliArgs& cli, bool realtime) {
  const std::string* mode = cli.Option("--dut");
  const std::string* timeout = cli.Option("--dut-timeout-s");
  if (mode != nullptr && *mode != "inproc" && *mode != "process") {
    return rig::MakeError("--dut \"" + *mode + "\": expected inproc or process");
  }
  const bool process = mode != nullptr && *mode == "process";
  if (timeout != nullptr && !process) return rig::MakeError("--dut-timeout-s needs --dut process");
  if (!process) return DutFactory();
  ProcessDutOptions options;
  if (timeout != nullptr) {
    char* end = nullptr;
    options.answer_timeout_s = std::strtod(timeout->c_str(), &end);
    if (timeout->empty() || *end != '\0') {
      return rig::MakeError("--dut-timeout-s \"" + *timeout + "\" is not a number");
    }
  }
  if (auto valid = ValidateProcessDutOptions(options); !valid) {
    return rig::MakeError("--dut-timeout-s: " + valid.error().message);
  }
  std::shared_ptr<const rig::SteadyClock> dut_clock;
  if (realtime) {
    dut_clock = std::make_shared<const rig::SteadyClock>();
    options.wall_clock = dut_clock.get();
  }
  return DutFactory([options, dut_clock](
                        const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
                        double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    auto dut = ProcessDut::Start(FirmwareFor(config), std::move(bus), control_period_s, options);
    if (!dut) return dut.error();
    return std::unique_ptr<DutPort>(std::move(dut).value());
  });
}

// Removes every `flag` from args; true if there was one.
bool TakeFlag(std::vector<std::string>& args, const std::string& flag) {
  const auto removed = std::remove(args.begin() + 1, args.end(), flag);
  const bool present = removed != args.end();
  args.erase(removed, args.end());
  return present;
}

rig::Result<RunOptions> ParseRunOptions(std::vector<std::string> args) {
  // --reference is the default; the flag stays accepted for scripts written when it was not.
  const bool with_reference = TakeFlag(args, "--reference");
  const bool without_reference = TakeFlag(args, "--no-reference");
  const bool realtime = TakeFlag(args, "--realtime");
  // The reference is a lockstep simulation of the scene; a real-time trace is not reproducible.
  if (realtime && with_reference) {
    return rig::MakeError(
        "--reference compares lockstep runs; it cannot be combined with --realtime");
  }
  if (with_reference && without_reference) {
    return rig::MakeError("--reference and --no-reference contradict each other");
  }
  auto parsed = ParseCliArgs(
      args, {"--out", "--seed", "--dut", "--dut-timeout-s", "--reference-cache", "--rt-priority"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (cli.positional.size() != 1) {
    return rig::MakeError("run takes one scenario file or folder");
  }
  RunOptions options;
  options.reference = !without_reference && !realtime;
  options.realtime = realtime;
  if (const std::string* cache = cli.Option("--reference-cache")) {
    options.reference_cache_dir = *cache;
  }
  options.target = cli.positional.front();
  if (const std::string* out = cli.Option("--out")) options.out_dir = *out;
  if (const std::string* seed_text = cli.Option("--seed")) {
    auto seed = ParseSeed(*seed_text);
    if (!seed) return seed.error();
    options.seed = seed.value();
  }
  if (const std::string* priority = cli.Option("--rt-priority")) {
    if (!realtime) return rig::MakeError("--rt-priority applies to --realtime runs only");
    auto value = ParseWholeNumberOption("--rt-priority", *priority, 0, rig::kMaxFifoPriority);
    if (!value) return value.error();
    options.realtime_priority = value.value();
  }
  auto dut = ParseDutOptions(cli, realtime);
  if (!dut) return dut.error();
  options.dut_factory = std::move(dut).value();
  return options;
}

struct ScenarioOutcome {
  std::string name;
  int exit_code = kExitBadInput;
  proto::Report report;
};

rig::Result<proto::Report> RunToDirectory(const proto::Scenario& spec, const std::string& spec_path,
                                          const fs::path& out_dir, const RunOptions& options,
                                          const ReferenceSource* reference, const Streams& io) {
  // Locked, and reading "incomplete" until the final report replaces it.
  auto folder = RunOutputFolder::Claim(out_dir.string(), spec.name(), spec_path);
  if (!folder) return folder.error();
  // The trace and the CAN log are written from inside the stepping loop, whose wall time is the
  // run's real-time factor: rig::OutputFile buffers 1 MiB of them between write system calls.
  auto trace_file = rig::OutputFile::Create((out_dir / "trace.csv").string());
  if (!trace_file) return trace_file.error();
  auto can_log_file = rig::OutputFile::Create((out_dir / "can.log").string());
  if (!can_log_file) return can_log_file.error();
  std::ostream& trace = trace_file.value()->stream();
  std::ostream& can_log = can_log_file.value()->stream();

  const rig::SteadyClock wall_clock;
  const std::int64_t setup_start_ns = wall_clock.NowNs();
  ScenarioConfig config =
      ResolveScenario(spec, options.seed, fs::path(spec_path).parent_path().string());
  if (auto set_up =
          SetUpTactile(spec, config, options.field_maps, options.calibrations, io.stop_requested);
      !set_up) {
    return rig::MakeError(spec_path + ": " + set_up.error().message);
  }
  // One capture for the plots and the comparison with the reference.
  CapturedTrace captured;
  const auto keep_sample = [&](const TraceSample& sample) { captured.Add(sample); };
  std::optional<rig::ScopedFifoScheduling> scheduling;
  if (options.realtime && options.realtime_priority > 0) {
    // Before the run starts its dut process, which inherits the policy.
    scheduling.emplace(options.realtime_priority);
    if (!scheduling->granted()) {
      io.err << spec_path << ": " << scheduling->description()
             << "; the timing figures are the default scheduler's\n";
    }
  }
  // A real-time loop does not spend its period on rewriting the report (about 0.4 ms, up to 3):
  // its folder says "incomplete" without how far.
  std::function<void(double)> reached;
  if (!options.realtime) {
    reached = [&](double simulated_s) { folder.value().Reached(simulated_s, io.err); };
  }
  proto::Report report = RunScenario(config, {&trace, &can_log, &io.err, keep_sample, reached},
                                     {&wall_clock, io.stop_requested, options.dut_factory,
                                      options.realtime ? &wall_clock : nullptr});
  if (options.realtime) {
    report.mutable_timing()->set_scheduling(scheduling ? scheduling->description()
                                                       : "default scheduler (--rt-priority 0)");
  }
  scheduling.reset();  // writing files and plots is no real-time work
  report.set_spec_file(spec_path);
  // Calibrating at start and tabulating field maps happen before the first tick; the real-time
  // factor is the stepping loop's, and this is the rest.
  report.set_setup_s(static_cast<double>(wall_clock.NowNs() - setup_start_ns) / 1e9 -
                     report.wall_s());
  auto plots = WriteRunPlots(captured, config.envelopes, config.gripper.enabled, out_dir.string());
  if (!plots) return plots.error();
  for (const std::string& plot : plots.value()) report.add_plots(plot);
  if (reference != nullptr && report.stop_reason() == "completed") {
    RunControl reference_control;
    reference_control.wall_clock = &wall_clock;
    reference_control.stop_requested = io.stop_requested;
    auto error = FidelityErrorOf(config, captured, spec, fs::path(spec_path).parent_path().string(),
                                 *reference, reference_control);
    // Without a reference the run still has its verdict; the report then has no fidelity error.
    if (error) {
      *report.mutable_fidelity_error() = std::move(error).value();
    } else {
      io.err << spec_path << ": no fidelity error: " << error.error().message << "\n";
    }
  }
  if (auto closed = trace_file.value()->Close(); !closed) return closed.error();
  if (auto closed = can_log_file.value()->Close(); !closed) return closed.error();
  if (auto written = folder.value().Finish(report); !written) return written.error();
  return report;
}

ScenarioOutcome RunOneFile(const std::string& path, const fs::path& out_dir,
                           const RunOptions& options, const ReferenceSource* reference,
                           const Streams& io) {
  ScenarioOutcome outcome;
  outcome.name = fs::path(path).stem().string();
  auto spec = LoadScenario(path);
  if (!spec) {
    io.err << spec.error().message << "\n";
    return outcome;
  }
  auto report = RunToDirectory(spec.value(), path, out_dir, options, reference, io);
  if (!report) {
    io.err << "hilrig: " << report.error().message << "\n";
    return outcome;
  }
  outcome.report = std::move(report).value();
  outcome.exit_code = outcome.report.passed() ? kExitPass : kExitCheckFailed;
  return outcome;
}

void PrintRun(const ScenarioOutcome& outcome, const Streams& io) {
  for (const proto::EnvelopeResult& result : outcome.report.envelopes()) {
    io.out << FormatEnvelopeLine(result) << "\n";
  }
  for (const proto::TimingCheckResult& check : outcome.report.timing_checks()) {
    io.out << FormatTimingCheckLine(check) << "\n";
  }
  for (const std::string& line : FormatRealtimeTiming(outcome.report.timing())) {
    io.out << line << "\n";
  }
  for (const proto::ObjectOutcome& object : outcome.report.objects()) {
    io.out << FormatObjectLine(object) << "\n";
  }
  if (outcome.report.has_fidelity_error()) {
    io.out << FormatFidelityErrorLine(outcome.report.fidelity_error(),
                                      outcome.report.objects_size() > 0)
           << "\n";
  }
  io.out << FormatTimingLine(outcome.report) << std::endl;
}

std::string SummaryRow(const ScenarioOutcome& outcome) {
  const char* verdict = outcome.exit_code == kExitPass       ? "PASS"
                        : outcome.exit_code == kExitBadInput ? "INVALID"
                                                             : "FAIL";
  int met = 0;
  for (const auto& result : outcome.report.envelopes()) met += result.meets_expectation() ? 1 : 0;
  char row[200];
  std::snprintf(row, sizeof(row), "%-28s %-8s %3d/%-3d %12.0fx  %s", outcome.name.c_str(), verdict,
                met, outcome.report.envelopes_size(), outcome.report.real_time_factor(),
                outcome.report.stop_reason().c_str());
  return row;
}

// The reference every run of one command compares with, and the cache that keeps it.
struct ReferenceSetup {
  std::optional<ReferenceCache> cache;
  ReferenceSource source;
};

std::unique_ptr<ReferenceSetup> MakeReferenceSetup(const RunOptions& options, const Streams& io) {
  if (!options.reference) return nullptr;
  auto setup = std::make_unique<ReferenceSetup>();
  setup->source.fidelity = ReferenceFidelity(false);
  setup->source.notes = &io.err;
  auto identity = ExecutableIdentity();
  if (identity) {
    setup->cache.emplace(options.reference_cache_dir.value_or(DefaultReferenceCacheDir()), &io.err);
    setup->source.cache = &*setup->cache;
    setup->source.code_identity = identity.value();
  } else {
    io.err << "hilrig: reference cache off (" << identity.error().message << ")\n";
  }
  return setup;
}

int RunFolder(const RunOptions& options, const Streams& io) {
  const auto listed = ScenarioFilesIn(options.target);
  if (!listed) {
    io.err << "hilrig run: " << listed.error().message << "\n";
    return kExitBadInput;
  }
  const std::vector<std::string>& files = listed.value();
  if (files.empty()) {
    io.err << options.target << ": no *.textproto scenario in this folder\n";
    return kExitBadInput;
  }
  const fs::path out_root = options.out_dir.value_or("hilrig_out");
  // Two folder runs into one root would run the same scenarios into the same folders.
  const auto root = rig::FolderLock::Acquire(out_root.string());
  if (!root) {
    io.err << "hilrig run: " << root.error().message << "\n";
    return kExitBadInput;
  }
  const std::unique_ptr<ReferenceSetup> reference = MakeReferenceSetup(options, io);
  std::vector<ScenarioOutcome> outcomes;
  for (const std::string& file : files) {
    if (io.stop_requested != nullptr && io.stop_requested->load()) break;
    io.out << "== " << file << "\n";
    const fs::path out_dir = out_root / fs::path(file).stem();
    outcomes.push_back(
        RunOneFile(file, out_dir, options, reference ? &reference->source : nullptr, io));
    if (outcomes.back().exit_code != kExitBadInput) PrintRun(outcomes.back(), io);
  }
  int exit_code = kExitPass;
  io.out << "\n"
         << "scenario                     verdict  checks   real-time  stop\n";
  for (const ScenarioOutcome& outcome : outcomes) {
    io.out << SummaryRow(outcome) << "\n";
    exit_code = std::max(exit_code, outcome.exit_code);
  }
  if (outcomes.size() < files.size()) exit_code = std::max(exit_code, kExitCheckFailed);
  return exit_code;
}

int RunCommand(const std::vector<std::string>& args, const Streams& io) {
  auto options = ParseRunOptions(args);
  if (!options) {
    io.err << "hilrig run: " << options.error().message << "\n" << kUsage;
    return kExitBadInput;
  }
  const SetupCaches caches = MakeSetupCaches(options.value().reference_cache_dir, io.err);
  options.value().field_maps = caches.field_maps.get();
  options.value().calibrations = caches.calibrations.get();
  const std::string& target = options.value().target;
  std::error_code error;
  const fs::file_status status = fs::status(target, error);
  if (fs::is_directory(status)) return RunFolder(options.value(), io);
  if (status.type() == fs::file_type::not_found) {
    io.err << target << ": no such file or folder\n";
    return kExitBadInput;
  }
  if (error) {  // a link loop, a folder on the way that cannot be searched
    io.err << target << ": " << error.message() << "\n";
    return kExitBadInput;
  }
  const fs::path out_dir =
      options.value().out_dir.value_or((fs::path("hilrig_out") / fs::path(target).stem()).string());
  const std::unique_ptr<ReferenceSetup> reference = MakeReferenceSetup(options.value(), io);
  const ScenarioOutcome outcome =
      RunOneFile(target, out_dir, options.value(), reference ? &reference->source : nullptr, io);
  if (outcome.exit_code != kExitBadInput) PrintRun(outcome, io);
  return outcome.exit_code;
}

int CheckCommand(const std::vector<std::string>& args, const Streams& io) {
  if (args.size() < 2) {
    io.err << "hilrig check: needs at least one scenario file\n" << kUsage;
    return kExitBadInput;
  }
  int exit_code = kExitPass;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (rig::StopRequested(io.stop_requested)) {
      io.err << "hilrig check: interrupted before " << args[i] << "\n";
      return kExitCheckFailed;
    }
    std::error_code error;
    if (fs::is_directory(args[i], error)) {
      io.err << args[i] << ": is a folder; check takes scenario files\n";
      exit_code = kExitBadInput;
      continue;
    }
    const auto spec = LoadScenario(args[i]);
    if (!spec) {
      io.err << spec.error().message << "\n";
      exit_code = kExitBadInput;
      continue;
    }
    io.out << args[i] << ": ok (" << spec.value().envelopes_size() << " envelopes, "
           << spec.value().simulation().duration_s() << " s)\n";
  }
  return exit_code;
}

}  // namespace

int RunCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
           const std::atomic<bool>* stop_requested, std::istream* in) {
  const Streams io{out, err, stop_requested};
  if (args.empty()) {
    err << kUsage;
    return kExitBadInput;
  }
  if (args[0] == "run") return RunCommand(args, io);
  if (args[0] == "check") return CheckCommand(args, io);
  if (args[0] == "bench") return BenchCommand(args, io);
  if (args[0] == "calibrate") return CalibrateCommand(args, io);
  if (args[0] == "accuracy") return AccuracyCommand(args, io);
  if (args[0] == "decode") {
    return in != nullptr ? DecodeCommand(args, io, *in) : DecodeStandardInput(args, io);
  }
  if (args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    out << kUsage;
    return kExitPass;
  }
  err << "hilrig: unknown command \"" << args[0] << "\"\n" << kUsage;
  return kExitBadInput;
}

}  // namespace hilrig::host
