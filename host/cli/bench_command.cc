#include "host/cli/bench_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "host/cache/setup_caches.h"
#include "host/cli/cli.h"
#include "host/cli/command_help.h"
#include "host/report/report_files.h"
#include "host/report/scatter_plot.h"
#include "host/scenario/scenario_loader.h"
#include "host/work_precision/work_precision.h"
#include "rig/clock.h"
#include "rig/folder_lock.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr int kPlotColumns = 3;

struct BenchOptions {
  fs::path out_dir;
  std::vector<std::string> scene_files;
  std::optional<double> duration_s;
  std::optional<int> timing_repeats;
  bool quick = false;
};

std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, ',')) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

// A scene is a path to a spec, or a name under the scenarios folder.
std::string SceneFile(const std::string& scene, const fs::path& scenarios_dir) {
  if (scene.ends_with(".textproto")) return scene;
  return (scenarios_dir / (scene + ".textproto")).string();
}

rig::Result<BenchOptions> ParseBenchOptions(std::vector<std::string> args) {
  BenchOptions options;
  const auto quick = std::remove(args.begin() + 1, args.end(), std::string("--quick"));
  options.quick = quick != args.end();
  args.erase(quick, args.end());
  auto parsed =
      ParseCliArgs(args, {"--out", "--scenes", "--scenarios", "--duration-s", "--timing-repeats"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (!cli.positional.empty()) return rig::MakeError("unexpected argument " + cli.positional[0]);
  const std::string* out = cli.Option("--out");
  if (out == nullptr || out->empty()) return rig::MakeError("--out DIR is required");
  options.out_dir = *out;
  const std::string* scenarios = cli.Option("--scenarios");
  const fs::path scenarios_dir = scenarios != nullptr ? *scenarios : "scenarios";
  const std::string* scenes = cli.Option("--scenes");
  if (scenes != nullptr && *scenes == "all") {
    auto all = ScenarioFilesIn(scenarios_dir.string());
    if (!all) return all.error();
    options.scene_files = std::move(all).value();
  } else {
    for (const std::string& scene :
         SplitCommas(scenes != nullptr ? *scenes : "balloon_grasp,load_ramp")) {
      options.scene_files.push_back(SceneFile(scene, scenarios_dir));
    }
  }
  if (options.scene_files.empty()) return rig::MakeError("--scenes names no scene");
  if (const std::string* duration = cli.Option("--duration-s")) {
    auto value = ParseDurationOption(*duration);
    if (!value) return value.error();
    options.duration_s = value.value();
  }
  if (const std::string* repeats = cli.Option("--timing-repeats")) {
    auto value = ParseWholeNumberOption("--timing-repeats", *repeats, 1, 1000);
    if (!value) return value.error();
    options.timing_repeats = value.value();
  }
  return options;
}

rig::Result<void> WriteOutputs(const std::vector<SceneResult>& scenes, const fs::path& out_dir) {
  if (auto written =
          WriteTextFile((out_dir / "work_precision.csv").string(), WorkPrecisionCsv(scenes));
      !written) {
    return written.error();
  }
  return WriteTextFile((out_dir / "work_precision.svg").string(),
                       RenderScatterGrid(WorkPrecisionPlots(scenes), kPlotColumns));
}

}  // namespace

int BenchCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto parsed = ParseBenchOptions(args);
  if (!parsed) {
    io.err << "hilrig bench: " << parsed.error().message << "\n" << HelpPointer("bench");
    return kExitBadInput;
  }
  const BenchOptions& options = parsed.value();
  std::vector<std::pair<std::string, proto::Scenario>> specs;
  for (const std::string& file : options.scene_files) {
    auto spec = LoadScenario(file);
    if (!spec) {
      io.err << spec.error().message << "\n";
      return kExitBadInput;
    }
    specs.emplace_back(file, std::move(spec).value());
  }
  // One sweep at a time writes into the folder.
  const auto folder = rig::FolderLock::Acquire(options.out_dir.string());
  if (!folder) {
    io.err << "hilrig bench: " << folder.error().message << "\n";
    return kExitBadInput;
  }
  const rig::SteadyClock wall_clock;
  const SetupCaches caches = MakeSetupCaches(std::nullopt, io.err);
  SweepOptions sweep;
  sweep.quick = options.quick;
  sweep.duration_s = options.duration_s;
  sweep.progress = &io.err;
  sweep.calibrations = caches.calibrations.get();
  sweep.film_models = caches.film_models.get();
  // A quick sweep is for tests: one timed run each, since every run's setup (field maps) costs
  // more than its 3 s of stepping.
  if (options.quick) sweep.timing_repeats = 1;
  if (options.timing_repeats) sweep.timing_repeats = *options.timing_repeats;
  // The files are rewritten after every scene, so a sweep that is interrupted or fails in a later
  // scene keeps the scenes it finished (a full sweep takes about 14 minutes).
  std::vector<SceneResult> scenes;
  for (const auto& [file, spec] : specs) {
    io.out << "== " << file << "\n";
    auto scene = SweepScene(spec, fs::path(file).parent_path().string(), sweep,
                            {&wall_clock, io.stop_requested, {}});
    if (!scene) {
      io.err << "hilrig bench: " << scene.error().message << "\n";
      if (!scenes.empty()) {
        io.err << "hilrig bench: " << options.out_dir.string() << " keeps the " << scenes.size()
               << " scene(s) finished before it\n";
      }
      return kExitCheckFailed;
    }
    io.out << FormatParetoTables(scene.value()) << std::endl;
    scenes.push_back(std::move(scene).value());
    if (auto written = WriteOutputs(scenes, options.out_dir); !written) {
      io.err << "hilrig bench: " << written.error().message << "\n";
      return kExitBadInput;
    }
  }
  io.out << "wrote " << (options.out_dir / "work_precision.csv").string() << " and "
         << (options.out_dir / "work_precision.svg").string() << "\n";
  return kExitPass;
}

}  // namespace hilrig::host
