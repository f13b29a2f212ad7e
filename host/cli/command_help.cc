#include "host/cli/command_help.h"

#include <array>
#include <set>

#include "host/cli/build_info.h"
#include "host/cli/replay_command.h"
#include "host/cli/run_command.h"
#include "rig/command_args.h"

namespace hilrig::host {
namespace {

constexpr std::string_view kCheckUsage =
    "  hilrig check FILE.textproto...\n"
    "      validate scenario specs: every problem with its field path, and a warning when a\n"
    "      run would write more than is sensible\n";

constexpr std::string_view kSweepUsage =
    "  hilrig sweep SWEEP.textproto --out DIR [--jobs N] [--keep-runs] [--set PATH=VALUE,...]\n"
    "      (--set: numbers of every case's scenario, before the axes; failing.txt carries them)\n"
    "  hilrig sweep SWEEP.textproto --out DIR --slurm [--jobs SHARDS] [--partition P]\n"
    "               [--max-parallel K] [--wait]\n"
    "      a Slurm job array of --jobs shards, default 64, and a merge job after it\n"
    "  hilrig sweep SWEEP.textproto --out DIR --shard I/N   one shard, as a task runs it\n"
    "  hilrig sweep --merge DIR                             gather the shards' results\n";

constexpr std::string_view kCompareUsage =
    "  hilrig compare BASE CANDIDATE [--out FILE]\n"
    "      BASE, CANDIDATE: two run folders, two folder runs (hilrig run DIR/) or two sweep\n"
    "      folders; exit 1 when the candidate is worse; --out writes the comparison as JSON\n"
    "      (two sweeps: also the cases whose verdict flipped, listed, not graded)\n"
    "      [--margin-tolerance F] (a margin may shrink by F of the base's, default 0.1)\n"
    "      [--pass-rate-tolerance P] (default 0)\n"
    "      [--confidence C] (a pass-rate drop counts when significant at C, default 0.95)\n"
    "      [--trace-atol A] [--trace-rtol R] (default 1e-9, 1e-6)\n";

constexpr std::string_view kBenchUsage =
    "  hilrig bench --out DIR [--scenes a,b|all] (default balloon_grasp,load_ramp)\n"
    "      [--scenarios DIR] (where the scenes are, default scenarios/) [--duration-s S]\n"
    "      [--timing-repeats N] (more timings of a cheap run, fastest kept; default 20)\n"
    "      [--quick] (3 s of each scene, 2 integrators x 2 steps, 2 field levels)\n";

constexpr std::string_view kCalibrateUsage =
    "  hilrig calibrate --out DIR [--seed N] [--field F]\n"
    "      the tactile calibration jigs; writes DIR/calibration.textproto\n";

constexpr std::string_view kAccuracyUsage =
    "  hilrig accuracy --calibration FILE --out DIR [--seed N] [--field F] [--dut-filter N]\n"
    "      held-out force error with and without compensation: accuracy.json, accuracy.html\n"
    "  hilrig accuracy --budget --out DIR [--seed N] [--field F] [--dut-filter N]\n"
    "      the error per sensor effect: budget.json, budget.html\n"
    "      (--dut-filter: the DUT's mean over the last N forces, 1-16; default 3, as a "
    "scene's)\n";

constexpr std::string_view kDecodeUsage =
    "  hilrig decode --calibration FILE < readings.txt\n"
    "      each line 'bx by bz' (tesla) -> 'sx sy sz' or 'invalid <reason>'\n";

constexpr std::string_view kListenUsage =
    "  hilrig listen --can URI [--frames N]\n"
    "      print a CAN bus's frames as candump does\n"
    "      URI: emulated, udp:BASE_PORT[:INDEX[:COUNT]], socketcan:IFACE, gs_usb[:SERIAL]\n";

constexpr std::string_view kHelpUsage =
    "  hilrig help [COMMAND]   every command, or one command's options\n"
    "  hilrig COMMAND --help   the same for COMMAND\n"
    "  hilrig --version        the commit and build type of this build\n";

const std::array<CommandHelp, 11> kCommands = {{
    {"run", "run a scenario, or every scenario in a folder", kRunUsage},
    {"check", "validate scenario specs", kCheckUsage},
    {"sweep", "run and grade a sweep's cases, here or on Slurm", kSweepUsage},
    {"compare", "is a candidate run or sweep worse than its base? (exit 1)", kCompareUsage},
    {"replay", "replay a run's recorded DUT traffic on a DUT (exit 1: it differs)", kReplayUsage},
    {"bench", "the work-precision sweep of integrators, fields and sensor effects", kBenchUsage},
    {"calibrate", "calibrate the tactile sensors", kCalibrateUsage},
    {"accuracy", "held-out force error, and the error per sensor effect", kAccuracyUsage},
    {"decode", "decode magnetometer readings with a calibration", kDecodeUsage},
    {"listen", "print a CAN bus's frames", kListenUsage},
    {"help", "this overview, or one command's options", kHelpUsage},
}};

}  // namespace

std::span<const CommandHelp> Commands() { return kCommands; }

const CommandHelp* FindCommand(std::string_view name) {
  for (const CommandHelp& command : kCommands) {
    if (command.name == name) return &command;
  }
  return nullptr;
}

std::string Overview() {
  std::string out = "usage: hilrig COMMAND [ARGS]   (" + VersionLine() + ")\ncommands:\n";
  for (const CommandHelp& command : kCommands) {
    std::string name(command.name);
    name.resize(12, ' ');
    out.append("  ").append(name).append(command.summary).append("\n");
  }
  return out +
         "`hilrig help COMMAND` or `hilrig COMMAND --help` gives a command's options.\n"
         "Exit codes: 0 every check met its expected verdict, 1 a check did not or the run was "
         "cut\n"
         "short, 2 bad input or usage.\n";
}

std::string CommandUsage(const CommandHelp& command) {
  return "usage:\n" + std::string(command.usage);
}

std::string HelpPointer(std::string_view command) {
  return command.empty() ? "see `hilrig help`\n"
                         : "see `hilrig help " + std::string(command) + "`\n";
}

std::string UnknownCommand(const std::string& name) {
  std::set<std::string> names;
  for (const CommandHelp& command : kCommands) names.emplace(command.name);
  return "hilrig: unknown command \"" + name + "\"" + rig::DidYouMean(name, names) + "\n";
}

}  // namespace hilrig::host
