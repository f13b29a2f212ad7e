#include "host/cli/run_command.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "host/cache/setup_caches.h"
#include "host/cli/build_info.h"
#include "host/cli/cli.h"
#include "host/cli/command_help.h"
#include "host/linked_dut/dut_choice.h"
#include "host/pipeline/run_pipeline.h"
#include "host/report/report_files.h"
#include "host/report/stop_reason.h"
#include "host/report/suite_page.h"
#include "host/scenario/scenario_loader.h"
#include "host/sweep/shell_words.h"
#include "rig/clock.h"
#include "rig/folder_lock.h"
#include "rig/realtime_scheduling.h"

namespace hilrig::host {

const char kRunUsage[] =
    "  hilrig run FILE.textproto [--out DIR] [--seed N]   run one scenario\n"
    "      [--set PATH=VALUE,...] (set numbers of the spec: object.mass_kg=0.25)\n"
    "  hilrig run DIR/ [--out DIR] [--seed N]             run every *.textproto in DIR\n"
    "      [--duration-s S] (only the first S seconds: later timeline entries and envelopes\n"
    "      that open later are left out)\n"
    "      run options: --dut inproc|process (the DUT in this process, the default, or in\n"
    "      its own dut_emu process over the HIL link, lockstep) [--dut-timeout-s S]\n"
    "      [--dut-link shm|tcp] (with --dut process: the link in shared memory, the default,\n"
    "      or over TCP on loopback with the CAN frames on a loopback UDP bus)\n"
    "      --dut inproc-float (in this process, in single precision as on the target)\n"
    "      --dut exec:PROGRAM[,ARG...] (a program of your own in dut_emu's place: started\n"
    "      as PROGRAM ARG... and the link's arguments; --dut-link, --can and --dut-timeout-s\n"
    "      as for process; docs/your-dut.md)\n"
    "      --dut listen:ADDRESS:PORT[,token=FILE] (wait up to 60 s for a program you start to\n"
    "      dial ADDRESS:PORT over TCP, proving the token in FILE, default ./hilrig_link_token,\n"
    "      made when missing; its CAN bus is udp:PORT+1:1:2 unless --can names one)\n"
    "      --dut-link line (with exec: or listen:: the DUT speaks the DUT-side library's\n"
    "      link over TCP, dialling the link at PORT and the sensor bridge at PORT+1; exec:\n"
    "      adds --connect 127.0.0.1:PORT to its arguments; docs/your-dut.md)\n"
    "      (how long a dut process may take to answer a tick; default 1, 10 for qemu)\n"
    "      [--realtime]\n"
    "      (pace the run by the wall clock, the DUT answering asynchronously; reports loop\n"
    "      period, late ticks and DUT latency and grades the spec's timing envelopes)\n"
    "      [--rt-priority N] (the real-time loop and its dut process run under SCHED_FIFO\n"
    "      at N, 1-99, default 50; 0 keeps the default scheduler; refused: a warning)\n"
    "      [--can socketcan:IFACE] (with --dut process, exec: or serial:: the sensors' CAN\n"
    "      frames cross that interface to the dut process or the board's own CAN port, as on\n"
    "      a bench; their timing then follows the wall clock, so such a run means something\n"
    "      with --realtime)\n"
    "      --dut serial:DEVICE[,baud=N][,bridge=DEVICE][,bridge_baud=N] (a board on a serial\n"
    "      line, the sensor nodes' UART bridge on the second device; by default the link at\n"
    "      2000000 baud and the bridge at 921600, as the firmware image sets them)\n"
    "      --dut qemu [--target-image ELF] (the firmware image on QEMU's STM32F405; default\n"
    "      build-target/dut_fw_stm32f405.elf, made by ./scripts/build-target)\n"
    "      --dut mavlink-emu (PX4's stand-in, dut_emu --mavlink, driven over MAVLink as PX4\n"
    "      SITL is, lockstep only; the run folder gets mavlink.tlog; docs/mavlink.md)\n"
    "      --dut px4-sitl[:PORT] (wait up to 60 s for PX4 SITL on its simulator port, 4560\n"
    "      unless PORT is given, and its offboard link on udp 14540; docs/px4.md)\n"
    "      --dut px4-hitl:DEVICE[,baud=N] (PX4 on a board over its serial port, both MAVLink\n"
    "      links on it, default 921600 baud; real time only, add --realtime; docs/px4.md)\n"
    "      --dut mavlink-emu-hitl (PX4's stand-in on a pseudo-terminal, driven as a board is,\n"
    "      with --realtime)\n"
    "run writes report.json, junit.xml, trace.csv, can.log and run.mcap (the trace as MCAP\n"
    "channels for Foxglove; --no-mcap leaves it out; docs/mcap.md) into --out (default\n"
    "hilrig_out/<scenario>) and compares the trace with the scene's reference run (tight\n"
    "integrator and field, kept in a cache per build: --reference-cache DIR, default\n"
    "~/.cache/hilrig/reference; DIR/field_maps and DIR/calibrations keep tabulated field maps\n"
    "and calibrations, with or without the reference); --no-reference skips it.\n";

namespace {

namespace fs = std::filesystem;

// SCHED_FIFO priority of a real-time run unless --rt-priority says otherwise: the middle of the
// range, the default of ros2_control's controller manager.
constexpr int kDefaultRealtimePriority = 50;

struct RunOptions {
  std::string target;
  std::optional<std::string> out_dir;
  std::optional<std::uint64_t> seed;
  std::optional<double> duration_s;  // --duration-s: only the scene's first seconds
  std::vector<std::pair<std::string, double>> overrides;  // --set
  bool reference = true;  // --no-reference: do not compare with the reference run
  bool run_log = true;    // --no-mcap: no run.mcap
  std::optional<std::string> reference_cache_dir;    // --reference-cache
  DutFactory dut_factory;                            // --dut process; unset: in process
  bool realtime = false;                             // --realtime: paced by the wall clock
  int realtime_priority = kDefaultRealtimePriority;  // --rt-priority; 0: default scheduler
  FilmFieldModels* film_models = nullptr;            // films shared between the runs of one command
  const FileCalibrationStore* calibrations = nullptr;  // calibrations kept between runs
  proto::Provenance provenance;  // this build and the command line, for every run's report
};

}  // namespace

rig::Result<DutFactory> ParseDutOptions(const CliArgs& cli, bool realtime, const CliStreams& io) {
  const auto word = [&cli](const char* option) -> std::optional<std::string> {
    const std::string* value = cli.Option(option);
    return value != nullptr ? std::optional<std::string>(*value) : std::nullopt;
  };
  const DutArguments arguments{word("--dut"), word("--dut-timeout-s"), word("--dut-link"),
                               word("--can"), word("--target-image")};
  auto choice = ParseDutChoice(arguments);
  if (!choice) return choice.error();
  return MakeDutFactory(choice.value(), realtime, DutFactorySeams{io.stop_requested, &io.err});
}

namespace {

rig::Result<RunOptions> ParseRunOptions(std::vector<std::string> args, const CliStreams& io) {
  // --reference is the default; the flag stays accepted for scripts written when it was not.
  const bool with_reference = TakeFlag(args, "--reference");
  const bool without_reference = TakeFlag(args, "--no-reference");
  const bool realtime = TakeFlag(args, "--realtime");
  const bool without_log = TakeFlag(args, "--no-mcap");
  // The reference is a lockstep simulation of the scene; a real-time trace is not reproducible.
  if (realtime && with_reference) {
    return rig::MakeError(
        "--reference compares lockstep runs; it cannot be combined with --realtime");
  }
  if (with_reference && without_reference) {
    return rig::MakeError("--reference and --no-reference contradict each other");
  }
  auto parsed = ParseCliArgs(
      args,
      {"--out", "--seed", "--dut", "--dut-timeout-s", "--dut-link", "--can", "--reference-cache",
       "--rt-priority", "--target-image", "--duration-s", "--set"},
      {"--reference", "--no-reference", "--realtime", "--no-mcap"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (cli.positional.size() != 1) {
    return rig::MakeError("run takes one scenario file or folder");
  }
  RunOptions options;
  options.reference = !without_reference && !realtime;
  options.realtime = realtime;
  options.run_log = !without_log;
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
  if (const std::string* duration = cli.Option("--duration-s")) {
    auto value = ParseDurationOption(*duration);
    if (!value) return value.error();
    options.duration_s = value.value();
  }
  if (const std::string* sets = cli.Option("--set")) {
    auto parsed_sets = ParseSetOption(*sets);
    if (!parsed_sets) return parsed_sets.error();
    options.overrides = std::move(parsed_sets).value();
  }
  if (const std::string* priority = cli.Option("--rt-priority")) {
    if (!realtime) return rig::MakeError("--rt-priority applies to --realtime runs only");
    auto value = ParseWholeNumberOption("--rt-priority", *priority, 0, rig::kMaxFifoPriority);
    if (!value) return value.error();
    options.realtime_priority = value.value();
  }
  auto dut = ParseDutOptions(cli, realtime, io);
  if (!dut) return dut.error();
  options.dut_factory = std::move(dut).value();
  return options;
}

// This build and `hilrig` followed by `args` (args[0] is "run"), as a report records them.
proto::Provenance CommandProvenance(const std::vector<std::string>& args) {
  proto::Provenance provenance;
  provenance.set_rig_commit(ThisBuild().commit);
  provenance.set_build_type(ThisBuild().build_type);
  std::string line = "hilrig";
  for (const std::string& arg : args) line.append(" ").append(ShellQuoted(arg));
  provenance.set_command_line(line);
  return provenance;
}

struct ScenarioOutcome {
  std::string name;
  int exit_code = kExitBadInput;
  bool ran = false;   // false: the run never started, its report is empty
  std::string error;  // why it never started
  proto::Report report;
};

ScenarioOutcome RunOneFile(const std::string& path, const fs::path& out_dir,
                           const RunOptions& options, const ReferenceSource* reference,
                           const CliStreams& io) {
  ScenarioOutcome outcome;
  outcome.name = fs::path(path).stem().string();
  RunRequest request;
  request.spec_path = path;
  request.out_dir = out_dir.string();
  request.run_log = options.run_log;
  request.seed = options.seed;
  request.duration_s = options.duration_s;
  request.overrides = options.overrides;
  request.dut_factory = options.dut_factory;
  request.realtime_priority = options.realtime_priority;
  request.film_models = options.film_models;
  request.calibrations = options.calibrations;
  request.reference = reference;
  request.provenance = options.provenance;
  const rig::SteadyClock wall_clock;
  const RunSeams seams{&wall_clock, options.realtime ? &wall_clock : nullptr, io.stop_requested,
                       &io.err};
  RunPipelineResult result = RunPipeline(request, seams);
  if (const RunError* error = std::get_if<RunError>(&result)) {
    // A spec that cannot be read says so itself; the rest is the run's.
    io.err << (error->failure == RunFailure::kBadSpec ? "" : "hilrig: ") << error->message << "\n";
    outcome.error = error->message;
    // Stopped in its set-up, the run fails as an interrupted run does; its input is not at fault.
    if (error->failure == RunFailure::kInterrupted) {
      outcome.exit_code = kExitCheckFailed;
      SetStop({StopReason::kInterrupted, ""}, outcome.report);
    }
    return outcome;
  }
  outcome.ran = true;
  RunOutcome& run = std::get<RunOutcome>(result);
  outcome.report = std::move(run.report);
  outcome.exit_code = run.verdict == RunVerdict::kPass ? kExitPass : kExitCheckFailed;
  return outcome;
}

void PrintRun(const ScenarioOutcome& outcome, const CliStreams& io) {
  for (const proto::EnvelopeResult& result : outcome.report.envelopes()) {
    io.out << FormatEnvelopeLine(result) << "\n";
  }
  for (const proto::TimingCheckResult& check : outcome.report.timing_checks()) {
    io.out << FormatTimingCheckLine(check) << "\n";
  }
  if (outcome.report.has_target()) io.out << FormatTargetLine(outcome.report.target()) << "\n";
  for (const proto::TimingCheckResult& check : outcome.report.target_checks()) {
    io.out << FormatTimingCheckLine(check, "target") << "\n";
  }
  for (const std::string& line : FormatRealtimeTiming(outcome.report.timing())) {
    io.out << line << "\n";
  }
  for (const proto::ObjectOutcome& object : outcome.report.objects()) {
    io.out << FormatObjectLine(object) << "\n";
  }
  if (outcome.report.has_dut_faults()) {
    io.out << FormatDutFaultLine(outcome.report.dut_faults()) << "\n";
  }
  if (outcome.report.has_fidelity_error()) {
    io.out << FormatFidelityErrorLine(outcome.report.fidelity_error(),
                                      outcome.report.objects_size() > 0)
           << "\n";
  }
  io.out << FormatTimingLine(outcome.report) << std::endl;
}

SuiteRow SuiteRowOf(const ScenarioOutcome& outcome, const fs::path& out_dir) {
  SuiteRow row;
  row.name = outcome.name;
  row.verdict = outcome.exit_code == kExitPass       ? SuiteVerdict::kPass
                : outcome.exit_code == kExitBadInput ? SuiteVerdict::kInvalid
                                                     : SuiteVerdict::kFail;
  for (const auto& result : outcome.report.envelopes()) {
    row.envelopes_met += result.meets_expectation() ? 1 : 0;
  }
  row.envelopes = outcome.report.envelopes_size();
  row.real_time_factor = outcome.report.real_time_factor();
  row.stop_reason = outcome.report.stop_reason();
  row.error = outcome.error;
  std::error_code error;
  row.has_page = fs::is_regular_file(out_dir / "index.html", error);
  return row;
}

std::string SummaryRow(const SuiteRow& row) {
  char text[200];
  std::snprintf(text, sizeof(text), "%-28s %-8s %3d/%-3d %12.0fx  %s", row.name.c_str(),
                SuiteVerdictWord(row.verdict), row.envelopes_met, row.envelopes,
                row.real_time_factor, row.stop_reason.c_str());
  return text;
}

// DIR/index.html, written over after each scenario; a page that cannot be written is a warning,
// never the end of the run.
void WriteSuitePage(const std::string& folder, const fs::path& out_root,
                    const std::vector<SuiteRow>& rows, std::size_t files, const CliStreams& io) {
  const auto written =
      WriteTextFile((out_root / "index.html").string(), SuitePageHtml(folder, rows, files));
  if (!written) io.err << "hilrig run: warning: " << written.error().message << "\n";
}

int RunFolder(const RunOptions& options, const CliStreams& io) {
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
  const std::unique_ptr<ReferenceSetup> reference =
      options.reference ? MakeReferenceSetup(options.reference_cache_dir, io.err) : nullptr;
  std::vector<SuiteRow> rows;
  int exit_code = kExitPass;
  for (const std::string& file : files) {
    if (io.stop_requested != nullptr && io.stop_requested->load()) break;
    io.out << "== " << file << "\n";
    const fs::path out_dir = out_root / fs::path(file).stem();
    const ScenarioOutcome outcome =
        RunOneFile(file, out_dir, options, reference ? &reference->source : nullptr, io);
    if (outcome.ran) PrintRun(outcome, io);
    exit_code = std::max(exit_code, outcome.exit_code);
    rows.push_back(SuiteRowOf(outcome, out_dir));
    WriteSuitePage(options.target, out_root, rows, files.size(), io);
  }
  if (rows.empty()) WriteSuitePage(options.target, out_root, rows, files.size(), io);
  io.out << "\n"
         << "scenario                     verdict  checks   real-time  stop\n";
  for (const SuiteRow& row : rows) io.out << SummaryRow(row) << "\n";
  if (rows.size() < files.size()) {
    io.out << "INCOMPLETE (stopped): " << rows.size() << " of " << files.size()
           << " scenario files ran\n";
    exit_code = std::max(exit_code, kExitCheckFailed);
  }
  io.out << "summary page: " << (out_root / "index.html").string() << "\n";
  return exit_code;
}

}  // namespace

int RunCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseRunOptions(args, io);
  if (!options) {
    io.err << "hilrig run: " << options.error().message << "\n" << HelpPointer("run");
    return kExitBadInput;
  }
  options.value().provenance = CommandProvenance(args);
  const SetupCaches caches = MakeSetupCaches(options.value().reference_cache_dir, io.err);
  options.value().film_models = caches.film_models.get();
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
  const std::unique_ptr<ReferenceSetup> reference =
      options.value().reference ? MakeReferenceSetup(options.value().reference_cache_dir, io.err)
                                : nullptr;
  const ScenarioOutcome outcome =
      RunOneFile(target, out_dir, options.value(), reference ? &reference->source : nullptr, io);
  if (outcome.ran) PrintRun(outcome, io);
  return outcome.exit_code;
}

}  // namespace hilrig::host
