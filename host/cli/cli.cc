#include "host/cli/cli.h"

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/bench_command.h"
#include "host/cli/can_commands.h"
#include "host/cli/cli_args.h"
#include "host/cli/compare_command.h"
#include "host/cli/run_command.h"
#include "host/cli/sweep_command.h"
#include "host/cli/tactile_commands.h"
#include "host/scenario/output_size.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "rig/stop_request.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// The help `hilrig help` prints: each command's own usage, `run`'s first.
std::string Usage() {
  return std::string("usage:\n") + kRunUsage +
         "  hilrig check FILE.textproto...                     validate scenario specs\n"
         "  hilrig sweep SWEEP.textproto --out DIR [--jobs N] [--keep-runs]\n"
         "                                                     run and grade a sweep's cases\n"
         "      --slurm [--partition P] [--max-parallel K] [--wait] (a Slurm job array of --jobs\n"
         "      shards, default 64, and a merge job after it); --shard I/N (one shard, as a task\n"
         "      runs it); hilrig sweep --merge DIR gathers them\n"
         "  hilrig compare BASE CANDIDATE                      is the candidate worse? (exit 1)\n"
         "      two run folders or two sweep folders; [--margin-tolerance F] (a margin may shrink\n"
         "      by F of the base's, default 0.1) [--pass-rate-tolerance P] (default 0)\n"
         "      [--confidence C] (a pass-rate drop counts when significant at C, default 0.95)\n"
         "      [--trace-atol A] [--trace-rtol R] (default 1e-9, 1e-6) [--out FILE] (JSON)\n"
         "  hilrig bench --out DIR [--scenes a,b|all]          work-precision sweep\n"
         "      [--scenarios DIR] (where the scenes are, default scenarios/) [--duration-s S]\n"
         "      [--timing-repeats N] (more timings of a cheap run, fastest kept; default 20) "
         "[--quick]\n"
         "  hilrig calibrate --out DIR [--seed N] [--field F]  calibrate the tactile sensors\n"
         "  hilrig accuracy --calibration FILE --out DIR [--seed N] [--field F] [--dut-filter N]\n"
         "                                                     held-out force error\n"
         "      (--dut-filter: the DUT's mean over the last N forces, 1-16; default 3, as a "
         "scene's)\n"
         "  hilrig accuracy --budget --out DIR [--seed N] [--field F] [--dut-filter N]\n"
         "                                                     the error per sensor effect\n"
         "  hilrig decode --calibration FILE                   stdin 'bx by bz' (T) -> S\n"
         "  hilrig listen --can URI [--frames N]               print a CAN bus's frames (candump)\n"
         "      URI: emulated, udp:BASE_PORT[:INDEX[:COUNT]], socketcan:IFACE, gs_usb[:SERIAL]\n"
         "  hilrig help                                        this text\n"
         "Exit codes: 0 every check met its expected verdict, 1 a check did not or the run was "
         "cut\n"
         "short, 2 bad input or usage.\n";
}

int CheckCommand(const std::vector<std::string>& args, const CliStreams& io) {
  if (args.size() < 2) {
    io.err << "hilrig check: needs at least one scenario file\n" << Usage();
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
    const ScenarioConfig config =
        ResolveScenario(spec.value(), std::nullopt, fs::path(args[i]).parent_path().string());
    if (const auto warning = OutputSizeWarning(config)) {
      io.err << args[i] << ": warning: a run " << *warning << "\n";
    }
  }
  return exit_code;
}

}  // namespace

int RunCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
           const std::atomic<bool>* stop_requested, std::istream* in) {
  const CliStreams io{out, err, stop_requested};
  if (args.empty()) {
    err << Usage();
    return kExitBadInput;
  }
  if (args[0] == "run") return RunCommand(args, io);
  if (args[0] == "check") return CheckCommand(args, io);
  if (args[0] == "bench") return BenchCommand(args, io);
  if (args[0] == "sweep") return SweepCommand(args, io);
  if (args[0] == "compare") return CompareCommand(args, io);
  if (args[0] == "calibrate") return CalibrateCommand(args, io);
  if (args[0] == "accuracy") return AccuracyCommand(args, io);
  if (args[0] == "listen") return ListenCommand(args, io);
  if (args[0] == "decode") {
    return in != nullptr ? DecodeCommand(args, io, *in) : DecodeStandardInput(args, io);
  }
  if (args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    out << Usage();
    return kExitPass;
  }
  err << "hilrig: unknown command \"" << args[0] << "\"\n" << Usage();
  return kExitBadInput;
}

}  // namespace hilrig::host
