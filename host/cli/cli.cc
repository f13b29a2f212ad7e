#include "host/cli/cli.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/bench_command.h"
#include "host/cli/build_info.h"
#include "host/cli/can_commands.h"
#include "host/cli/cli_args.h"
#include "host/cli/command_help.h"
#include "host/cli/compare_command.h"
#include "host/cli/replay_command.h"
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

int CheckCommand(const std::vector<std::string>& args, const CliStreams& io) {
  if (args.size() < 2) {
    io.err << "hilrig check: needs at least one scenario file\n" << HelpPointer("check");
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
    err << Overview();
    return kExitBadInput;
  }
  if (args[0] == "--version" || args[0] == "version") {
    out << VersionLine() << "\n";
    return kExitPass;
  }
  if (args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    if (args.size() < 2) {
      out << Overview();
      return kExitPass;
    }
    const CommandHelp* command = FindCommand(args[1]);
    if (command == nullptr) {
      err << UnknownCommand(args[1]) << HelpPointer();
      return kExitBadInput;
    }
    out << CommandUsage(*command);
    return kExitPass;
  }
  const CommandHelp* command = FindCommand(args[0]);
  if (command == nullptr) {
    err << UnknownCommand(args[0]) << HelpPointer();
    return kExitBadInput;
  }
  // `CMD --help` anywhere among its arguments asks for the help, not for a file called --help.
  if (std::any_of(args.begin() + 1, args.end(),
                  [](const std::string& arg) { return arg == "--help" || arg == "-h"; })) {
    out << CommandUsage(*command);
    return kExitPass;
  }
  if (args[0] == "run") return RunCommand(args, io);
  if (args[0] == "check") return CheckCommand(args, io);
  if (args[0] == "bench") return BenchCommand(args, io);
  if (args[0] == "sweep") return SweepCommand(args, io);
  if (args[0] == "compare") return CompareCommand(args, io);
  if (args[0] == "replay") return ReplayCommand(args, io);
  if (args[0] == "calibrate") return CalibrateCommand(args, io);
  if (args[0] == "accuracy") return AccuracyCommand(args, io);
  if (args[0] == "listen") return ListenCommand(args, io);
  return in != nullptr ? DecodeCommand(args, io, *in) : DecodeStandardInput(args, io);
}

}  // namespace hilrig::host
