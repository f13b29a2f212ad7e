#include "host/cli/tactile_commands.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>
#include <vector>

#include "dut_fw/tactile_processor.h"
#include "fixtures/calibration/accuracy_budget.h"
#include "fixtures/calibration/calibration_file.h"
#include "fixtures/calibration/calibration_procedure.h"
#include "host/cli/cli.h"
#include "host/report/accuracy_page.h"
#include "host/report/report_files.h"
#include "host/scenario/scenario_config.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "rig/bounded_line.h"
#include "rig/folder_lock.h"
#include "rig/stop_request.h"
#include "rig/stoppable_input.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// A reading is three numbers; 4 KiB is far past any such line and bounds what one line can hold.
constexpr std::size_t kMaxDecodeLineBytes = 4096;

struct TactileOptions {
  std::string out_dir;
  std::string calibration_file;
  std::uint64_t seed = 1;
  std::shared_ptr<const FilmFieldModel> film;
  std::string fidelity;
  // accuracy's --dut-filter: the DUT a scene flies unless it sets force_average_samples.
  int dut_filter_samples = static_cast<int>(kDefaultForceAverageSamples);
};

// Parses the options the tactile commands share; `needs_out` / `needs_calibration` say which
// are required. A map level's tabulation ends early on `stop_requested`.
rig::Result<TactileOptions> ParseTactileOptions(const std::vector<std::string>& args,
                                                bool needs_out, bool needs_calibration,
                                                const std::atomic<bool>* stop_requested,
                                                bool takes_dut_filter = false) {
  std::set<std::string> known = {"--out", "--seed", "--field", "--calibration"};
  if (takes_dut_filter) known.insert("--dut-filter");
  auto parsed = ParseCliArgs(args, known);
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (!cli.positional.empty()) return rig::MakeError("unexpected argument " + cli.positional[0]);
  TactileOptions options;
  if (const auto* out = cli.Option("--out")) options.out_dir = *out;
  if (needs_out && options.out_dir.empty()) return rig::MakeError("--out DIR is required");
  if (const auto* file = cli.Option("--calibration")) options.calibration_file = *file;
  if (needs_calibration && options.calibration_file.empty()) {
    return rig::MakeError("--calibration FILE is required");
  }
  if (const auto* seed_text = cli.Option("--seed")) {
    auto seed = ParseSeed(*seed_text);
    if (!seed) return seed.error();
    options.seed = seed.value();
  }
  if (const auto* filter = cli.Option("--dut-filter")) {
    auto samples = ParseWholeNumberOption("--dut-filter", *filter, 1,
                                          static_cast<int>(dut_fw::kMaxForceAverageSamples));
    if (!samples) return samples.error();
    options.dut_filter_samples = samples.value();
  }
  const auto* fidelity = cli.Option("--field");
  options.fidelity = fidelity != nullptr ? *fidelity : std::string(kDefaultFilmFidelity);
  if (needs_out) {  // only the commands that run the forward model need a film
    auto film = MakeFilmField(options.fidelity, nullptr, stop_requested);
    if (!film) return film.error();
    options.film = film.value();
  }
  return options;
}

std::string Format(const char* format, double a, double b, double c) {
  char line[128];
  std::snprintf(line, sizeof(line), format, a, b, c);
  return line;
}

void PrintCalibration(const proto::Calibration& calibration, std::ostream& out) {
  const auto& ours = calibration.film();
  const auto& paper = calibration.published_film();
  out << "film constants      k1          c1 (T)        k2          c2 (T)     cross-talk\n";
  char line[160];
  std::snprintf(line, sizeof(line), "  ours       %10.6f  %12.5e  %10.6f  %12.5e  %.3e\n",
                ours.k1(), ours.c1(), ours.k2(), ours.c2(), calibration.cross_talk_ours());
  out << line;
  std::snprintf(line, sizeof(line), "  published  %10.6f  %12.5e  %10.6f  %12.5e  %.3e\n",
                paper.k1(), paper.c1(), paper.k2(), paper.c2(), calibration.cross_talk_published());
  out << line << "F/T jig fit residuals (N)   rms x    rms y    rms z    max x    max y    max z\n";
  for (const auto& sensor : calibration.sensors()) {
    std::snprintf(line, sizeof(line), "  node %u %21s %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f\n",
                  sensor.node_id(), "", sensor.fit_rms_n().x(), sensor.fit_rms_n().y(),
                  sensor.fit_rms_n().z(), sensor.fit_max_n().x(), sensor.fit_max_n().y(),
                  sensor.fit_max_n().z());
    out << line;
  }
}

void PrintAccuracy(const proto::AccuracyReport& report, std::ostream& out) {
  out << "held-out loads: " << report.sensors() << " sensors x " << report.attitudes()
      << " attitudes x " << report.loads_per_attitude() << " loads, field "
      << report.field_fidelity() << ", DUT filter " << report.dut_filter_samples() << " sample(s)\n"
      << "condition        rmse x   rmse y   rmse z    max x    max y    max z   samples  "
         "flagged\n";
  for (const auto& condition : report.conditions()) {
    char line[200];
    std::snprintf(line, sizeof(line), "%-14s %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f %9u %8u\n",
                  condition.condition().c_str(), condition.rmse_n().x(), condition.rmse_n().y(),
                  condition.rmse_n().z(), condition.max_n().x(), condition.max_n().y(),
                  condition.max_n().z(), condition.samples(), condition.flagged());
    out << line;
  }
}

std::string AxisTriple(const proto::Vector3& v) {
  return Format("%8.4f %8.4f %8.4f", v.x(), v.y(), v.z());
}

void PrintBudget(const proto::AccuracyBudget& budget, std::ostream& out) {
  out << "force-error budget, compensated, held-out (N); field " << budget.field_fidelity()
      << ", DUT filter " << budget.dut_filter_samples() << " sample(s)\n"
      << "configuration                     rmse x   rmse y   rmse z    max x    max y    max z"
         "    p95 x    p95 y    p95 z\n";
  for (const proto::BudgetRow& row : budget.rows()) {
    const proto::ConditionAccuracy& c = row.compensated();
    char name[40];
    std::snprintf(name, sizeof(name), "%-31s", row.configuration().c_str());
    out << name << " " << AxisTriple(c.rmse_n()) << " " << AxisTriple(c.max_n()) << " "
        << AxisTriple(c.p95_n()) << "\n";
  }
  const proto::ConditionAccuracy& decoder = budget.decoding_floor();
  out << "decoder alone (exact field)     " << AxisTriple(decoder.rmse_n()) << " "
      << AxisTriple(decoder.max_n()) << " " << AxisTriple(decoder.p95_n()) << "\n"
      << "floor (none)                    " << AxisTriple(budget.floor_rmse_n()) << "\n"
      << "floor + effects alone (RSS)     " << AxisTriple(budget.combined_rmse_n()) << "\n"
      << "measured total (all)            " << AxisTriple(budget.total_rmse_n()) << "\n"
      << "gap (together beyond alone)     " << AxisTriple(budget.gap_rmse_n()) << "\n";
}

// Three numbers separated by blanks; strtod, unlike operator>>, reads "nan" and "inf", which the
// decoder then flags itself.
std::optional<Eigen::Vector3d> ParseFieldLine(const std::string& line) {
  Eigen::Vector3d field_t;
  const char* cursor = line.c_str();
  for (int axis = 0; axis < 3; ++axis) {
    char* end = nullptr;
    field_t(axis) = std::strtod(cursor, &end);
    if (end == cursor) return std::nullopt;
    cursor = end;
  }
  while (*cursor == ' ' || *cursor == '\t' || *cursor == '\r') ++cursor;
  if (cursor != line.c_str() + line.size()) return std::nullopt;  // also a NUL inside the line
  return field_t;
}

// A result's JSON and its page (host/report/accuracy_page.h) in `out_dir`, the JSON first; the
// paths written, for the "wrote" lines.
rig::Result<std::vector<fs::path>> WriteJsonAndPage(const google::protobuf::Message& message,
                                                    const std::string& page_html,
                                                    const std::string& out_dir,
                                                    const char* json_file, const char* page_file) {
  const fs::path json = fs::path(out_dir) / json_file;
  if (auto written = WriteJsonFile(message, json.string()); !written) return written.error();
  const fs::path page = fs::path(out_dir) / page_file;
  if (auto written = WriteTextFile(page.string(), page_html); !written) return written.error();
  return std::vector<fs::path>{json, page};
}

// An error once a stop was requested is the stop's doing: the command was cut short.
int Fail(const CliStreams& io, const std::string& command, const std::string& message) {
  io.err << "hilrig " << command << ": " << message << "\n";
  return rig::StopRequested(io.stop_requested) ? kExitCheckFailed : kExitBadInput;
}

}  // namespace

int CalibrateCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options =
      ParseTactileOptions(args, /*needs_out=*/true, /*needs_calibration=*/false, io.stop_requested);
  if (!options) return Fail(io, "calibrate", options.error().message);
  const auto folder = rig::FolderLock::Acquire(options.value().out_dir);
  if (!folder) return Fail(io, "calibrate", folder.error().message);
  const fixtures::CalibrationBench bench;
  std::optional<proto::Calibration> calibrated = fixtures::CalibrateUnlessStopped(
      bench, *options.value().film, options.value().seed, io.stop_requested);
  if (!calibrated) {
    io.err << "hilrig calibrate: interrupted, nothing written\n";
    return kExitCheckFailed;
  }
  proto::Calibration& calibration = *calibrated;
  calibration.set_field_fidelity(options.value().fidelity);
  const fs::path path = fs::path(options.value().out_dir) / "calibration.textproto";
  if (auto written = fixtures::WriteCalibrationFile(calibration, path.string()); !written) {
    return Fail(io, "calibrate", written.error().message);
  }
  PrintCalibration(calibration, io.out);
  io.out << "wrote " << path.string() << "\n";
  return kExitPass;
}

// `accuracy --budget`: every configuration calibrated and measured (AccuracyBudget), budget.json
// and its page budget.html.
int BudgetCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseTactileOptions(args, /*needs_out=*/true, /*needs_calibration=*/false,
                                     io.stop_requested, /*takes_dut_filter=*/true);
  if (!options) return Fail(io, "accuracy", options.error().message);
  const auto folder = rig::FolderLock::Acquire(options.value().out_dir);
  if (!folder) return Fail(io, "accuracy", folder.error().message);
  const fixtures::CalibrationBench bench;
  const auto progress = [&io](const std::string& configuration) {
    io.err << "hilrig accuracy: budget: calibrating and measuring with " << configuration << "\n";
  };
  fixtures::BudgetOptions budget_options;
  budget_options.accuracy.dut_filter_samples = options.value().dut_filter_samples;
  std::optional<proto::AccuracyBudget> budget =
      fixtures::MeasureBudgetUnlessStopped(bench, *options.value().film, options.value().seed,
                                           io.stop_requested, progress, budget_options);
  if (!budget) {
    io.err << "hilrig accuracy: interrupted, nothing written\n";
    return kExitCheckFailed;
  }
  budget->set_field_fidelity(options.value().fidelity);
  const auto written = WriteJsonAndPage(*budget, BudgetPageHtml(*budget), options.value().out_dir,
                                        kBudgetJsonFile, kBudgetPageFile);
  if (!written) return Fail(io, "accuracy", written.error().message);
  PrintBudget(*budget, io.out);
  for (const fs::path& path : written.value()) io.out << "wrote " << path.string() << "\n";
  return kExitPass;
}

int AccuracyCommand(const std::vector<std::string>& args_in, const CliStreams& io) {
  std::vector<std::string> args = args_in;
  if (TakeFlag(args, "--budget")) return BudgetCommand(args, io);
  auto options = ParseTactileOptions(args, /*needs_out=*/true, /*needs_calibration=*/true,
                                     io.stop_requested, /*takes_dut_filter=*/true);
  if (!options) return Fail(io, "accuracy", options.error().message);
  const auto calibration = fixtures::ReadCalibrationFile(options.value().calibration_file);
  if (!calibration) return Fail(io, "accuracy", calibration.error().message);
  const auto folder = rig::FolderLock::Acquire(options.value().out_dir);
  if (!folder) return Fail(io, "accuracy", folder.error().message);
  const fixtures::CalibrationBench bench;
  fixtures::AccuracyOptions accuracy;
  accuracy.dut_filter_samples = options.value().dut_filter_samples;
  // Held-out means other noise and other loads than calibration's: a seed of its own.
  std::optional<proto::AccuracyReport> measured = fixtures::MeasureAccuracyUnlessStopped(
      bench, *options.value().film, calibration.value(), options.value().seed + 1000,
      io.stop_requested, accuracy);
  if (!measured) {
    io.err << "hilrig accuracy: interrupted, nothing written\n";
    return kExitCheckFailed;
  }
  proto::AccuracyReport& report = *measured;
  report.set_field_fidelity(options.value().fidelity);
  const auto written = WriteJsonAndPage(report, AccuracyPageHtml(report), options.value().out_dir,
                                        kAccuracyJsonFile, kAccuracyPageFile);
  if (!written) return Fail(io, "accuracy", written.error().message);
  PrintAccuracy(report, io.out);
  for (const fs::path& path : written.value()) io.out << "wrote " << path.string() << "\n";
  return kExitPass;
}

int DecodeCommand(const std::vector<std::string>& args, const CliStreams& io, std::istream& in) {
  auto options =
      ParseTactileOptions(args, /*needs_out=*/false, /*needs_calibration=*/true, io.stop_requested);
  if (!options) return Fail(io, "decode", options.error().message);
  const auto calibration = fixtures::ReadCalibrationFile(options.value().calibration_file);
  if (!calibration) return Fail(io, "decode", calibration.error().message);
  const dut_fw::FilmConstants<double> film = fixtures::FilmConstantsOf(calibration.value());
  int exit_code = kExitPass;
  std::string line;
  for (std::size_t line_number = 1;; ++line_number) {
    const rig::LineRead read = rig::ReadBoundedLine(in, kMaxDecodeLineBytes, line);
    // Reading flushed the answers so far (stdin is tied to stdout): stop once they cannot go out.
    if (!io.out) return kExitBadInput;
    if (read == rig::LineRead::kEnd) break;
    if (read == rig::LineRead::kReadError) {
      return Fail(io, "decode",
                  "cannot read standard input after line " + std::to_string(line_number - 1));
    }
    if (read == rig::LineRead::kTooLong) {
      return Fail(io, "decode",
                  "line " + std::to_string(line_number) + ": longer than " +
                      std::to_string(kMaxDecodeLineBytes) +
                      " bytes; not a list of readings, stopped");
    }
    const auto field_t = ParseFieldLine(line);
    if (!field_t) {
      io.out << "invalid malformed_line\n";
      exit_code = kExitBadInput;
      continue;
    }
    const auto s = dut_fw::ComputeS<double>(film, *field_t);
    if (s.ok()) {
      io.out << Format("%.9g %.9g %.9g", s.s.x(), s.s.y(), s.s.z()) << "\n";
    } else {
      io.out << "invalid " << dut_fw::DecodeStatusName(s.status) << "\n";
    }
  }
  io.out.flush();
  return io.out ? exit_code : kExitBadInput;
}

int DecodeStandardInput(const std::vector<std::string>& args, const CliStreams& io) {
  rig::StoppableLineBuf lines(STDIN_FILENO, io.stop_requested);
  std::istream in(&lines);
  const int exit_code = DecodeCommand(args, io, in);
  if (lines.stopped()) {
    io.err << "hilrig decode: interrupted; every whole line read before it was decoded\n";
    return kExitCheckFailed;
  }
  if (lines.error_number() != 0) {
    return Fail(io, "decode",
                std::string("cannot read standard input: ") + std::strerror(lines.error_number()));
  }
  return exit_code;
}

}  // namespace hilrig::host
