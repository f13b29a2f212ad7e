#include "host/cli/sweep_command.h"

#include <google/protobuf/text_format.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "host/cache/setup_caches.h"
#include "host/cli/cli.h"
#include "host/cli/command_help.h"
#include "host/cli/sweep_slurm.h"
#include "host/link/child_process.h"
#include "host/sweep/case_run.h"
#include "host/sweep/sweep_folder.h"
#include "host/sweep/sweep_merge.h"
#include "host/sweep/sweep_shard.h"
#include "host/sweep/sweep_statistics.h"
#include "rig/clock.h"
#include "rig/file_io.h"
#include "rig/folder_lock.h"
#include "rig/number_text.h"
#include "rig/printable_text.h"
#include "rig/stop_request.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxJobs = 256;
// A Slurm array's default size: enough tasks to fill a partition of a few nodes, few enough that
// each task's start is small next to its cases.
constexpr std::uint64_t kDefaultSlurmShards = 64;
constexpr int kMaxSlurmShards = 100'000;
constexpr int kMaxShardsAtOnce = 100'000;
constexpr std::int64_t kProgressPeriodNs = 1'000'000'000;
constexpr int kPollMs = 100;
// A shard asked to stop ends its running case at the next tick; a case of a QEMU DUT may take
// longer to wind down, so the grace is generous before SIGKILL.
constexpr int kShardStopGraceMs = 5000;

struct SweepOptions {
  std::string sweep_path;  // the spec, or DIR/sweep.textproto for --merge
  std::string out_dir;
  int jobs = 1;
  std::optional<ShardSpec> shard;
  bool jobs_given = false;
  bool merge_only = false;
  bool keep_runs = false;
  std::optional<std::string> cache_dir;
  bool slurm = false;  // submit the shards to Slurm instead of running them here
  bool wait = false;   // --slurm: return when the merge job has ended
  std::optional<std::string> partition;
  std::optional<std::uint32_t> max_parallel;
  std::vector<std::pair<std::string, double>> sets;  // --set: numbers of every case
};

int Usage(const CliStreams& io, const std::string& why) {
  io.err << "hilrig sweep: " << why << "\n" << HelpPointer("sweep");
  return kExitBadInput;
}

// --slurm's own options, which mean nothing without it.
rig::Result<void> ParseSlurmOptions(const CliArgs& cli, SweepOptions& options) {
  const std::string* partition = cli.Option("--partition");
  const std::string* max_parallel = cli.Option("--max-parallel");
  if (!options.slurm) {
    if (partition || max_parallel || options.wait) {
      return rig::MakeError("--partition, --max-parallel and --wait go with --slurm");
    }
    return {};
  }
  if (cli.Option("--shard")) return rig::MakeError("--slurm submits every shard; not --shard");
  if (partition) {
    if (partition->empty() || partition->find_first_of(" \t\n%") != std::string::npos) {
      return rig::MakeError("--partition \"" + *partition + "\" is no partition name");
    }
    options.partition = *partition;
  }
  if (max_parallel) {
    auto value = ParseWholeNumberOption("--max-parallel", *max_parallel, 1, kMaxShardsAtOnce);
    if (!value) return value.error();
    options.max_parallel = static_cast<std::uint32_t>(value.value());
  }
  return {};
}

rig::Result<SweepOptions> ParseSweepOptions(std::vector<std::string> args) {
  SweepOptions options;
  options.keep_runs = TakeFlag(args, "--keep-runs");
  options.slurm = TakeFlag(args, "--slurm");
  options.wait = TakeFlag(args, "--wait");
  auto parsed = ParseCliArgs(args, {"--out", "--jobs", "--shard", "--merge", "--reference-cache",
                                    "--partition", "--max-parallel", "--set"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (const std::string* merge = cli.Option("--merge")) {
    if (!cli.positional.empty() || cli.options.size() > 1 || options.slurm || options.wait ||
        options.keep_runs) {
      return rig::MakeError("--merge DIR takes nothing else");
    }
    options.merge_only = true;
    options.out_dir = *merge;
    options.sweep_path = (fs::path(*merge) / kResolvedSweepName).string();
    return options;
  }
  if (cli.positional.size() != 1) return rig::MakeError("sweep takes one sweep file");
  options.sweep_path = cli.positional.front();
  const std::string* out = cli.Option("--out");
  if (out == nullptr) return rig::MakeError("--out DIR is required");
  options.out_dir = *out;
  if (const std::string* cache = cli.Option("--reference-cache")) options.cache_dir = *cache;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  options.jobs = static_cast<int>(std::min<unsigned>(cores, kMaxJobs));
  if (const std::string* jobs = cli.Option("--jobs")) {
    auto value =
        ParseWholeNumberOption("--jobs", *jobs, 1, options.slurm ? kMaxSlurmShards : kMaxJobs);
    if (!value) return value.error();
    options.jobs = value.value();
    options.jobs_given = true;
  }
  if (auto slurm = ParseSlurmOptions(cli, options); !slurm.ok()) return slurm.error();
  if (const std::string* shard = cli.Option("--shard")) {
    if (cli.Option("--jobs"))
      return rig::MakeError("--shard runs one shard; --jobs does not apply");
    auto value = ParseShardSpec(*shard);
    if (!value) return value.error();
    options.shard = value.value();
  }
  if (const std::string* sets = cli.Option("--set")) {
    // A shard reads its sets from the folder's sweep.textproto, where the sweep wrote them.
    if (options.shard)
      return rig::MakeError("--shard runs the folder's sweep as written; not --set");
    auto parsed_sets = ParseSetOption(*sets);
    if (!parsed_sets) return parsed_sets.error();
    options.sets = std::move(parsed_sets).value();
  }
  return options;
}

// Every scenario path absolute and normal, as DIR/sweep.textproto holds them: the merge here then
// writes the same failing.txt and page as a `--merge DIR` elsewhere, whatever the working
// directory and however the sweep file named its scenarios.
void MakeScenarioPathsAbsolute(LoadedSweep& sweep) {
  for (SweepScenario& scenario : sweep.scenarios) {
    scenario.path = fs::absolute(scenario.path).lexically_normal().string();
  }
}

// The sweep as the shards and the merge read it (its scenario paths made absolute), so it loads
// from DIR whatever the working directory.
rig::Result<void> WriteResolvedSweep(const LoadedSweep& sweep, const std::string& out_dir) {
  proto::Sweep resolved = sweep.spec;
  resolved.clear_scenario();
  for (const SweepScenario& scenario : sweep.scenarios) resolved.add_scenario(scenario.path);
  std::string text;
  google::protobuf::TextFormat::PrintToString(resolved, &text);
  return rig::WriteFileAtomically((fs::path(out_dir) / kResolvedSweepName).string(),
                                  "# written by hilrig sweep: the sweep its shards run\n" + text);
}

// Counts the rows the running shards have written, reading only what is new each time, at most
// kMaxProgressReadBytes a file per poll. Only regular files are read, so a FIFO planted in shards/
// cannot block the sweep; a partial line past the row cap is dropped (the merge names it).
class ShardProgress {
 public:
  explicit ShardProgress(std::string out_dir) : folder_(fs::path(out_dir) / "shards") {}

  void Poll() {
    std::error_code error;
    for (fs::directory_iterator entry(folder_, error), end; !error && entry != end;
         entry.increment(error)) {
      if (entry->path().extension() == ".jsonl") ReadNew(entry->path().string());
    }
  }
  std::uint64_t done() const { return done_; }
  std::uint64_t not_passed() const { return not_passed_; }

 private:
  static constexpr std::size_t kMaxProgressReadBytes = std::size_t{1} << 20;
  static constexpr std::size_t kMaxPartialBytes = std::size_t{1} << 20;

  void ReadNew(const std::string& path) {
    auto fd = rig::OpenRegularFileForReading(path);
    if (!fd) return;
    auto& [offset, partial] = files_[path];
    std::string chunk(kMaxProgressReadBytes, '\0');
    const ssize_t got = ::pread(fd.value(), chunk.data(), chunk.size(), static_cast<off_t>(offset));
    ::close(fd.value());
    if (got <= 0) return;
    chunk.resize(static_cast<std::size_t>(got));
    offset += chunk.size();
    partial += chunk;
    for (std::size_t newline = partial.find('\n'); newline != std::string::npos;
         newline = partial.find('\n')) {
      // A line cut by a kill is not a finished case; the merge skips it too.
      const rig::Result<proto::SweepCaseResult> row = ParseShardRow(partial.substr(0, newline));
      if (row.ok()) {
        ++done_;
        if (row.value().outcome() != proto::SweepCaseResult::PASSED) ++not_passed_;
      }
      partial.erase(0, newline + 1);
    }
    if (partial.size() > kMaxPartialBytes) partial.clear();
  }

  fs::path folder_;
  std::map<std::string, std::pair<std::uint64_t, std::string>> files_;
  std::uint64_t done_ = 0;
  std::uint64_t not_passed_ = 0;
};

void PrintProgress(const std::string& name, std::uint64_t done, std::uint64_t total,
                   std::uint64_t not_passed, double elapsed_s, std::ostream& err) {
  err << name << ": " << done << "/" << total << " cases, " << not_passed << " not passed, "
      << std::lround(elapsed_s) << " s";
  if (done > 0 && done < total) {
    err << ", about " << std::lround(elapsed_s * double(total - done) / double(done)) << " s left";
  }
  err << std::endl;
}

// The sibling hilrig executable (the shards run it, and failing.txt names it).
rig::Result<std::string> HilrigExecutable() {
  auto dir = ExecutableDirectory();
  if (!dir) return dir.error();
  const std::string path = (fs::path(dir.value()) / "hilrig").string();
  if (::access(path.c_str(), X_OK) != 0) {
    return rig::MakeError("no hilrig executable beside this one at " + path);
  }
  return path;
}

// Runs the sweep's shards as `jobs` processes of `hilrig`, printing progress; on a stop request
// asks them to stop and waits. Fails when a shard cannot start or fails.
rig::Result<void> RunShardProcesses(const LoadedSweep& sweep, const SweepOptions& options,
                                    const std::string& hilrig, const CliStreams& io) {
  const std::string resolved = (fs::path(options.out_dir) / kResolvedSweepName).string();
  std::vector<ChildProcess> shards;
  for (int i = 1; i <= options.jobs; ++i) {
    std::vector<std::string> argv = {hilrig,
                                     "sweep",
                                     resolved,
                                     "--out",
                                     options.out_dir,
                                     "--shard",
                                     std::to_string(i) + "/" + std::to_string(options.jobs)};
    if (options.keep_runs) argv.push_back("--keep-runs");
    if (options.cache_dir) argv.insert(argv.end(), {"--reference-cache", *options.cache_dir});
    auto child = ChildProcess::Spawn(argv);
    if (!child)
      return rig::InContext("cannot start shard " + std::to_string(i) + ": ", child.error());
    shards.push_back(std::move(child).value());
  }
  const rig::SteadyClock clock;
  const std::int64_t start_ns = clock.NowNs();
  std::int64_t next_progress_ns = start_ns + kProgressPeriodNs;
  ShardProgress progress(options.out_dir);
  const std::uint64_t total = CaseCount(sweep);
  std::optional<std::string> failure;
  for (bool running = true; running;) {
    const timespec nap{0, kPollMs * 1'000'000L};
    ::nanosleep(&nap, nullptr);
    if (rig::StopRequested(io.stop_requested)) {
      for (ChildProcess& shard : shards) shard.Terminate(kShardStopGraceMs);
    }
    running = false;
    for (std::size_t i = 0; i < shards.size(); ++i) {
      if (!shards[i].PollExit()) {
        running = true;
      } else if (shards[i].exit_status() != 0 && !failure &&
                 !rig::StopRequested(io.stop_requested)) {
        failure = "shard " + std::to_string(i + 1) + " " + *shards[i].PollExit();
      }
    }
    const std::int64_t now_ns = clock.NowNs();
    if (now_ns >= next_progress_ns || !running) {
      next_progress_ns = now_ns + kProgressPeriodNs;
      progress.Poll();
      PrintProgress(sweep.spec.name(), progress.done(), total, progress.not_passed(),
                    double(now_ns - start_ns) * 1e-9, io.err);
    }
  }
  if (failure) return rig::MakeError(*failure);
  return {};
}

CaseRunSetup MakeCaseSetup(const LoadedSweep& sweep, const SweepOptions& options,
                           const SetupCaches& caches, const rig::Clock& clock,
                           const CliStreams& io) {
  CaseRunSetup setup;
  setup.wall_clock = &clock;
  setup.stop_requested = io.stop_requested;
  setup.film_models = caches.film_models.get();
  setup.calibrations = caches.calibrations.get();
  setup.runs_dir = (fs::path(options.out_dir) / "runs").string();
  setup.keep_all_runs = options.keep_runs || sweep.spec.keep_all_traces();
  return setup;
}

// "PASS  criterion 0  balloon_grasp / not_dropped  pass rate lower bound 0.996 >= 0.99".
std::string FormatCheckLine(const proto::SweepCriterionCheck& check) {
  const bool rate = check.kind() == proto::SweepCriterionCheck::PASS_RATE;
  std::ostringstream line;
  line << (check.passed() ? "PASS" : "FAIL") << "  criterion[" << check.criterion() << "]  "
       << check.scenario() << " / " << check.envelope() << "  "
       << (rate ? "pass rate (Wilson lower bound) " : "margin quantile ");
  if (check.has_measured()) {
    line << rig::NumberText(check.measured());
  } else {
    line << "not measured";
  }
  line << " >= " << rig::NumberText(check.limit());
  if (!check.note().empty()) line << "  (" << check.note() << ")";
  return line.str();
}

int PrintMerged(const LoadedSweep& sweep, const MergedSweep& merged, const std::string& out_dir,
                bool stopped, const CliStreams& io) {
  for (const proto::SweepCriterionCheck& check : merged.summary.check()) {
    io.out << FormatCheckLine(check) << "\n";
  }
  io.out << sweep.spec.name() << ": " << merged.finished << " of " << merged.cases << " cases, "
         << merged.not_passed << " not passed";
  if (merged.bad_lines > 0) io.out << ", " << merged.bad_lines << " shard lines refused";
  if (merged.conflicting_cases > 0) {
    io.out << ", " << merged.conflicting_cases << " cases with conflicting rows";
  }
  if (merged.unreadable_files > 0) {
    io.out << ", " << merged.unreadable_files << " unreadable shard files";
  }
  io.out << "; " << rig::PrintableText((fs::path(out_dir) / "summary.json").string()) << "\n";
  for (const std::string& problem : merged.problems) {
    io.err << sweep.spec.name() << ": " << rig::PrintableText(problem) << "\n";
  }
  if (stopped || merged.finished < merged.cases) {
    io.out << sweep.spec.name() << ": INCOMPLETE ("
           << (stopped                                                ? "stopped"
               : merged.finished + merged.bad_lines > merged.finished ? "cases missing or refused"
                                                                      : "cases missing")
           << "): the criteria are not graded as met\n";
    return kExitCheckFailed;
  }
  io.out << sweep.spec.name() << ": " << (merged.criteria_met ? "PASS" : "FAIL") << "\n";
  return merged.criteria_met ? kExitPass : kExitCheckFailed;
}

SlurmSweepJob MakeSlurmJob(const LoadedSweep& sweep, const SweepOptions& options,
                           const std::string& hilrig) {
  SlurmSweepJob job;
  job.name = sweep.spec.name();
  job.hilrig = hilrig;
  job.out_dir = fs::absolute(options.out_dir).lexically_normal().string();
  if (job.out_dir.size() > 1 && job.out_dir.back() == '/') job.out_dir.pop_back();
  job.shards = static_cast<std::uint32_t>(std::min<std::uint64_t>(
      options.jobs_given ? options.jobs : kDefaultSlurmShards, CaseCount(sweep)));
  job.partition = options.partition;
  job.max_parallel = options.max_parallel;
  job.keep_runs = options.keep_runs;
  return job;
}

// What a sweep that runs (here or on Slurm) holds while it prepares: its folder's lock, the
// checked Slurm job, the earlier sweep's outputs set aside.
struct PreparedSweep {
  rig::FolderLock lock;
  std::optional<SlurmSweepJob> slurm_job;
  std::string sbatch;
  EarlierSweepAside earlier;
};

// Everything that can refuse the sweep, checked before the folder changes; then the folder is
// locked, the earlier sweep's outputs set aside and this sweep's spec written. An error is the
// message to print (exit 2); the folder is then as it was.
rig::Result<PreparedSweep> PrepareSweep(LoadedSweep& sweep, const SweepOptions& options,
                                        const rig::Result<std::string>& hilrig) {
  if (!hilrig) return hilrig.error();
  std::optional<SlurmSweepJob> job;
  std::string sbatch;
  if (options.slurm) {
    job = MakeSlurmJob(sweep, options, hilrig.value());
    auto checked = CheckSlurmJob(*job);
    if (!checked) return checked.error();
    sbatch = checked.value();
  }
  auto lock = rig::FolderLock::Acquire(options.out_dir);
  if (!lock) return lock.error();
  auto earlier = EarlierSweepAside::Move(options.out_dir);
  if (!earlier) return earlier.error();
  MakeScenarioPathsAbsolute(sweep);
  if (auto written = WriteResolvedSweep(sweep, options.out_dir); !written.ok()) {
    earlier.value().PutBack();
    return written.error();
  }
  return PreparedSweep{std::move(lock).value(), std::move(job), std::move(sbatch),
                       std::move(earlier).value()};
}

// Submits the prepared sweep to Slurm. Returns the exit code when the command ends here (submitted
// without --wait, or refused); nothing when the merge job has ended and its results are to be
// printed.
std::optional<int> RunOnSlurm(const LoadedSweep& sweep, const SweepOptions& options,
                              PreparedSweep& prepared, const CliStreams& io) {
  const SlurmSweepJob& job = *prepared.slurm_job;
  // The merge job takes the folder's lock itself, so this process lets it go once it has set the
  // folder up: from submission to merge the folder is the cluster's.
  { const rig::FolderLock released(std::move(prepared.lock)); }
  auto submitted = SubmitSweepToSlurm(job, prepared.sbatch, options.wait, io.stop_requested);
  if (!submitted) {
    prepared.earlier.PutBack();
    io.err << "hilrig sweep: " << submitted.error().message << "\n";
    return kExitBadInput;
  }
  prepared.earlier.Drop();
  io.err << job.name << ": " << CaseCount(sweep) << " cases in " << job.shards
         << " array tasks: Slurm job " << submitted.value().array_job_id << ", merge job "
         << submitted.value().merge_job_id << " (scripts in " << job.out_dir << "/slurm/)\n";
  if (options.wait) return std::nullopt;
  io.out << job.name << ": submitted; the merged results appear in " << job.out_dir << " when job "
         << submitted.value().merge_job_id << " ends (hilrig sweep --merge " << job.out_dir
         << " prints them)\n";
  return kExitPass;
}

int RunOneShard(const LoadedSweep& sweep, const SweepOptions& opts, const CliStreams& io) {
  std::error_code error;
  fs::create_directories(opts.out_dir, error);
  if (error) {
    io.err << "hilrig sweep: cannot make " << opts.out_dir << ": " << error.message() << "\n";
    return kExitBadInput;
  }
  const SetupCaches caches = MakeSetupCaches(opts.cache_dir, io.err);
  const rig::SteadyClock clock;
  auto ran =
      RunShard(sweep, *opts.shard, opts.out_dir, MakeCaseSetup(sweep, opts, caches, clock, io));
  if (!ran) {
    io.err << "hilrig sweep: " << ran.error().message << "\n";
    return kExitCheckFailed;
  }
  return kExitPass;
}

int MergeAndPrint(const LoadedSweep& sweep, const SweepOptions& opts,
                  const std::string& hilrig_path, bool stopped, const CliStreams& io) {
  auto merged = MergeSweep(sweep, opts.out_dir, hilrig_path);
  if (!merged) {
    io.err << "hilrig sweep: " << merged.error().message << "\n";
    return kExitCheckFailed;
  }
  return PrintMerged(sweep, merged.value(), opts.out_dir, stopped, io);
}

// A merge writes the folder's results: not while a sweep or another merge is at it.
int LockedMerge(const LoadedSweep& sweep, const SweepOptions& opts, const std::string& hilrig_path,
                const CliStreams& io) {
  auto lock = rig::FolderLock::Acquire(opts.out_dir);
  if (!lock) {
    io.err << "hilrig sweep: " << lock.error().message << "\n";
    return kExitBadInput;
  }
  return MergeAndPrint(sweep, opts, hilrig_path, rig::StopRequested(io.stop_requested), io);
}

}  // namespace

int SweepCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseSweepOptions(args);
  if (!options) return Usage(io, options.error().message);
  auto sweep = LoadSweep(options.value().sweep_path);
  if (!sweep) {
    io.err << sweep.error().message << "\n";
    return kExitBadInput;
  }
  if (auto added = AddSweepSets(sweep.value(), options.value().sets); !added.ok()) {
    io.err << options.value().sweep_path << ": " << added.error().message << "\n";
    return kExitBadInput;
  }
  const SweepOptions& opts = options.value();
  const auto hilrig = HilrigExecutable();
  const std::string hilrig_path = hilrig ? hilrig.value() : "hilrig";
  // A shard runs inside a sweep that holds the folder (its parent, or a Slurm array's submitter).
  if (opts.shard) return RunOneShard(sweep.value(), opts, io);
  if (opts.merge_only) return LockedMerge(sweep.value(), opts, hilrig_path, io);
  auto prepared = PrepareSweep(sweep.value(), opts, hilrig);
  if (!prepared) {
    io.err << "hilrig sweep: " << prepared.error().message << "\n";
    return kExitBadInput;
  }
  if (opts.slurm) {
    if (const std::optional<int> ended = RunOnSlurm(sweep.value(), opts, prepared.value(), io)) {
      return *ended;
    }
    return LockedMerge(sweep.value(), opts, hilrig_path, io);
  }
  io.err << sweep.value().spec.name() << ": " << CaseCount(sweep.value()) << " cases in "
         << opts.jobs << " shard" << (opts.jobs == 1 ? "" : "s") << "\n";
  prepared.value().earlier.Drop();
  auto ran = RunShardProcesses(sweep.value(), opts, hilrig_path, io);
  if (!ran) io.err << "hilrig sweep: " << ran.error().message << "\n";
  const bool stopped = rig::StopRequested(io.stop_requested);
  return MergeAndPrint(sweep.value(), opts, hilrig_path, stopped, io);
}

}  // namespace hilrig::host
