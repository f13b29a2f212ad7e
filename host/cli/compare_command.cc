#include "host/cli/compare_command.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <tuple>

#include "host/cli/cli.h"
#include "host/cli/command_help.h"
#include "host/compare/case_changes.h"
#include "host/compare/comparison_text.h"
#include "host/compare/result_folder.h"
#include "host/compare/run_comparison.h"
#include "host/compare/runs_csv.h"
#include "host/compare/sweep_comparison.h"
#include "host/compare/trace_difference.h"
#include "host/report/report_files.h"
#include "proto/compare.pb.h"
#include "rig/input_file.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

struct CompareOptions {
  std::string base_dir;
  std::string candidate_dir;
  std::optional<std::string> out_file;
  proto::CompareTolerances tolerances;
};

int Usage(const CliStreams& io, const std::string& why) {
  io.err << "hilrig compare: " << why << "\n" << HelpPointer("compare");
  return kExitBadInput;
}

proto::CompareTolerances DefaultTolerances() {
  proto::CompareTolerances tolerances;
  tolerances.set_margin_fraction(0.1);
  tolerances.set_pass_rate_drop(0);
  tolerances.set_confidence(0.95);
  tolerances.set_trace_abs(1e-9);
  tolerances.set_trace_rel(1e-6);
  return tolerances;
}

// The option's value as a finite number in [min, max], when given.
rig::Result<void> ReadTolerance(const CliArgs& cli, const std::string& option, double min,
                                double max, void (proto::CompareTolerances::*set)(double),
                                proto::CompareTolerances& tolerances) {
  const std::string* text = cli.Option(option);
  if (text == nullptr) return {};
  auto value = rig::ParseNumber<double>(*text, option);
  if (!value) return value.error();
  if (!(value.value() >= min && value.value() <= max)) {
    return rig::MakeError(option + " must be from " + rig::NumberText(min) + " to " +
                          rig::NumberText(max) + ", not " + *text);
  }
  (tolerances.*set)(value.value());
  return {};
}

rig::Result<CompareOptions> ParseCompareOptions(const std::vector<std::string>& args) {
  auto parsed = ParseCliArgs(args, {"--margin-tolerance", "--pass-rate-tolerance", "--confidence",
                                    "--trace-atol", "--trace-rtol", "--out"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (cli.positional.size() != 2) return rig::MakeError("compare takes two folders");
  CompareOptions options{cli.positional[0], cli.positional[1], std::nullopt, DefaultTolerances()};
  if (const std::string* out = cli.Option("--out")) options.out_file = *out;
  using T = proto::CompareTolerances;
  constexpr double kHuge = 1e300;
  for (const auto& [option, min, max, set] :
       {std::tuple{"--margin-tolerance", 0.0, kHuge, &T::set_margin_fraction},
        std::tuple{"--pass-rate-tolerance", 0.0, 1.0, &T::set_pass_rate_drop},
        std::tuple{"--confidence", 0.0, 1.0, &T::set_confidence},
        std::tuple{"--trace-atol", 0.0, kHuge, &T::set_trace_abs},
        std::tuple{"--trace-rtol", 0.0, kHuge, &T::set_trace_rel}}) {
    if (auto read = ReadTolerance(cli, option, min, max, set, options.tolerances); !read) {
      return read.error();
    }
  }
  return options;
}

rig::Result<proto::RunComparison> CompareRunFolders(const std::string& base_dir,
                                                    const std::string& candidate_dir,
                                                    const proto::CompareTolerances& tolerances) {
  auto base = ReadRunReport(base_dir);
  if (!base) return base.error();
  auto candidate = ReadRunReport(candidate_dir);
  if (!candidate) return candidate.error();
  if (base.value().scenario() != candidate.value().scenario()) {
    return rig::MakeError("the runs are of different scenarios: " + base.value().scenario() +
                          " and " + candidate.value().scenario());
  }
  proto::RunComparison comparison = CompareRuns(base.value(), candidate.value(), tolerances);
  // Only regular files: a FIFO planted as a trace must not block the comparison.
  auto base_trace = rig::InputFile::Open(RunTracePath(base_dir));
  auto candidate_trace = rig::InputFile::Open(RunTracePath(candidate_dir));
  if (!base_trace || !candidate_trace) {
    comparison.mutable_trace()->set_problem(
        (base_trace ? candidate_trace.error() : base_trace.error()).message);
  } else {
    *comparison.mutable_trace() =
        CompareTraces(base_trace.value()->stream(), candidate_trace.value()->stream(), tolerances);
  }
  return comparison;
}

// Two folder runs, scene by scene: the run folders both have compared, the others listed.
rig::Result<proto::SuiteComparison> CompareSuiteFolders(const CompareOptions& options) {
  auto base = SuiteRunNames(options.base_dir);
  if (!base) return base.error();
  auto candidate = SuiteRunNames(options.candidate_dir);
  if (!candidate) return candidate.error();
  proto::SuiteComparison comparison;
  for (const std::string& name : base.value()) {
    if (!std::binary_search(candidate.value().begin(), candidate.value().end(), name)) {
      comparison.add_only_in_base(name);
      continue;
    }
    auto run =
        CompareRunFolders((fs::path(options.base_dir) / name).string(),
                          (fs::path(options.candidate_dir) / name).string(), options.tolerances);
    if (!run) return rig::InContext(name + ": ", run.error());
    for (const std::string& reason : run.value().reason())
      comparison.add_reason(name + ": " + reason);
    comparison.set_worse(comparison.worse() || run.value().worse());
    proto::SuiteComparison::Scene* scene = comparison.add_scene();
    scene->set_name(name);
    *scene->mutable_run() = std::move(run).value();
  }
  for (const std::string& name : candidate.value()) {
    if (!std::binary_search(base.value().begin(), base.value().end(), name)) {
      comparison.add_only_in_candidate(name);
    }
  }
  return comparison;
}

// The summaries graded, and the cases of runs.csv matched: a sweep folder without a readable
// runs.csv cannot be compared, as one without its summary cannot.
rig::Result<proto::SweepComparison> CompareSweepFolders(const CompareOptions& options) {
  auto base = ReadSweepSummary(options.base_dir);
  if (!base) return base.error();
  auto candidate = ReadSweepSummary(options.candidate_dir);
  if (!candidate) return candidate.error();
  auto base_cases = ReadRunsCsv(options.base_dir);
  if (!base_cases) return base_cases.error();
  auto candidate_cases = ReadRunsCsv(options.candidate_dir);
  if (!candidate_cases) return candidate_cases.error();
  proto::SweepComparison comparison =
      CompareSweeps(base.value(), candidate.value(), options.tolerances);
  *comparison.mutable_cases() = CompareCases(base_cases.value(), candidate_cases.value());
  return comparison;
}

const char* KindName(ResultFolderKind kind) {
  switch (kind) {
    case ResultFolderKind::kRun:
      return "a run";
    case ResultFolderKind::kSweep:
      return "a sweep";
    case ResultFolderKind::kSuite:
      return "a folder run";
  }
  return "unknown";
}

// Fills `comparison` from the two folders; fails when they are not of one kind or unreadable.
rig::Result<void> CompareFolders(const CompareOptions& options, proto::Comparison& comparison) {
  auto base_kind = ResultFolderKindOf(options.base_dir);
  if (!base_kind) return base_kind.error();
  auto candidate_kind = ResultFolderKindOf(options.candidate_dir);
  if (!candidate_kind) return candidate_kind.error();
  if (base_kind.value() != candidate_kind.value()) {
    return rig::MakeError("the folders hold different kinds of result (" +
                          std::string(KindName(base_kind.value())) + ", " +
                          KindName(candidate_kind.value()) + "): " + options.base_dir + ", " +
                          options.candidate_dir);
  }
  switch (base_kind.value()) {
    case ResultFolderKind::kRun: {
      auto run = CompareRunFolders(options.base_dir, options.candidate_dir, options.tolerances);
      if (!run) return run.error();
      *comparison.mutable_run() = std::move(run.value());
      return {};
    }
    case ResultFolderKind::kSweep: {
      auto sweep = CompareSweepFolders(options);
      if (!sweep) return sweep.error();
      *comparison.mutable_sweep() = std::move(sweep.value());
      return {};
    }
    case ResultFolderKind::kSuite: {
      auto suite = CompareSuiteFolders(options);
      if (!suite) return suite.error();
      *comparison.mutable_suite() = std::move(suite.value());
      return {};
    }
  }
  return rig::MakeError("unknown result folder kind");
}

}  // namespace

int CompareCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseCompareOptions(args);
  if (!options) return Usage(io, options.error().message);
  proto::Comparison comparison;
  comparison.set_base_dir(options.value().base_dir);
  comparison.set_candidate_dir(options.value().candidate_dir);
  *comparison.mutable_tolerances() = options.value().tolerances;
  if (auto compared = CompareFolders(options.value(), comparison); !compared) {
    io.err << "hilrig compare: " << compared.error().message << "\n";
    return kExitBadInput;
  }
  const bool sweep = comparison.has_sweep();
  const auto lines = comparison.has_run()     ? RunComparisonLines(comparison.run())
                     : comparison.has_suite() ? SuiteComparisonLines(comparison.suite())
                                              : SweepComparisonLines(comparison.sweep());
  const bool worse = comparison.has_run()     ? comparison.run().worse()
                     : comparison.has_suite() ? comparison.suite().worse()
                                              : comparison.sweep().worse();
  const auto& reasons = comparison.has_run()     ? comparison.run().reason()
                        : comparison.has_suite() ? comparison.suite().reason()
                                                 : comparison.sweep().reason();
  for (const auto& line : lines) io.out << line << "\n";
  for (const auto& line : VerdictLines(worse, reasons, comparison.tolerances(), sweep)) {
    io.out << line << "\n";
  }
  if (options.value().out_file) {
    if (auto written = WriteJsonFile(comparison, *options.value().out_file); !written) {
      io.err << "hilrig compare: " << written.error().message << "\n";
      return kExitBadInput;
    }
  }
  return worse ? kExitCheckFailed : kExitPass;
}

}  // namespace hilrig::host
