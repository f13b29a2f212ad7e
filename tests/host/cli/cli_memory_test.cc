// A run's memory does not grow with its simulated duration: `hilrig run` of a long hover peaks at
// the same resident size as a short one, give or take a few MiB, without a reference and with one
// (made with a cold cache, read from a warm one). The runs are
// child processes, so each one's peak resident size is its own (wait4's rusage).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

struct ChildPeak {
  int status = 0;
  long max_rss_kb = 0;
};

// Runs hilrig with `arguments` (its output to /dev/null) and waits for it, killing it after
// `deadline_s`; nullopt when it could not be started or ran out of time.
std::optional<ChildPeak> RunHilrigMeasured(const std::vector<std::string>& arguments,
                                           double deadline_s) {
  const std::string binary = ::hilrig::test_support::BinDir() + "/hilrig";
  std::vector<char*> argv = {const_cast<char*>(binary.c_str())};
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return std::nullopt;
  if (pid == 0) {
    const int null_fd = ::open("/dev/null", O_WRONLY);
    if (null_fd < 0 || ::dup2(null_fd, STDOUT_FILENO) < 0 || ::dup2(null_fd, STDERR_FILENO) < 0) {
      ::_exit(126);
    }
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  ChildPeak peak;
  rusage usage{};
  const timespec nap{0, 10'000'000};
  for (double waited_s = 0; waited_s < deadline_s; waited_s += 0.01) {
    const pid_t done = ::wait4(pid, &peak.status, WNOHANG, &usage);
    if (done == pid) {
      peak.max_rss_kb = usage.ru_maxrss;
      return peak;
    }
    if (done < 0) return std::nullopt;
    ::nanosleep(&nap, nullptr);
  }
  ::kill(pid, SIGKILL);
  ::wait4(pid, &peak.status, 0, &usage);
  return std::nullopt;
}

// Hover at 1 m, the trace at its default 100 Hz: no timeline, so any duration is the same scene.
fs::path WriteHoverSpec(const fs::path& dir) {
  const fs::path spec = dir / "hover.textproto";
  std::ofstream(spec) << "name: \"memory_hover\"\n"
                         "vehicle { initial_position_m { z: 1 } }\n"
                         "simulation { duration_s: 1 }\n"
                         "envelopes { name: \"altitude\" signal: ALTITUDE_ERROR_M upper: 0.05 }\n";
  return spec;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

constexpr const char* kNotTheRunsMemory =
    "under AddressSanitizer the resident size is its shadow memory and quarantine, not the run's";

TEST(CliMemoryTest, ALongRunPeaksAtTheResidentSizeOfAShortOne) {
  if (kAddressSanitizer) GTEST_SKIP() << kNotTheRunsMemory;
  const fs::path dir = FreshTestDir("cli_memory");
  const std::string spec = WriteHoverSpec(dir).string();
  // 60 s is past the first flush of trace.csv's 1 MiB buffer and the plots' first merge of
  // buckets; 2000 s of full-rate columns would be 9 MiB at 48 bytes a sample, ~2 s of wall time.
  const auto run = [&](const std::string& duration_s) {
    return RunHilrigMeasured(
        {"run", spec, "--no-reference", "--set", "simulation.duration_s=" + duration_s, "--out",
         (dir / ("out_" + duration_s)).string()},
        120);
  };
  const std::optional<ChildPeak> short_run = run("60");
  const std::optional<ChildPeak> long_run = run("2000");
  ASSERT_TRUE(short_run && long_run) << "hilrig did not start or did not finish in time";
  ASSERT_TRUE(WIFEXITED(short_run->status) && WEXITSTATUS(short_run->status) == 0);
  ASSERT_TRUE(WIFEXITED(long_run->status) && WEXITSTATUS(long_run->status) == 0);
  EXPECT_GT(short_run->max_rss_kb, 0);
  EXPECT_LT(long_run->max_rss_kb, short_run->max_rss_kb + 4 * 1024)
      << "peak resident size: " << short_run->max_rss_kb << " KiB over 60 s, "
      << long_run->max_rss_kb << " KiB over 2000 s";
  // The long run really ran its whole duration.
  EXPECT_NE(ReadFile(dir / "out_2000" / "report.json").find("\"simulated_s\": 2000"),
            std::string::npos);
}

// The comparison with the reference reads the reference from its cache entry as the run goes: it
// used to keep both runs' compared columns, about 17 KB a simulated second (warm cache) and 22 KB
// (cold), so 600 s peaked some 10 MiB above 60 s.
TEST(CliMemoryTest, ALongRunComparedWithItsReferencePeaksAtTheSizeOfAShortOne) {
  if (kAddressSanitizer) GTEST_SKIP() << kNotTheRunsMemory;
  const fs::path dir = FreshTestDir("cli_memory_reference");
  const std::string spec = WriteHoverSpec(dir).string();
  const std::string cache = (dir / "reference_cache").string();
  const auto run = [&](const std::string& duration_s, const std::string& out) {
    return RunHilrigMeasured({"run", spec, "--reference-cache", cache, "--set",
                              "simulation.duration_s=" + duration_s, "--out", (dir / out).string()},
                             120);
  };
  const std::optional<ChildPeak> short_run = run("60", "short");
  const std::optional<ChildPeak> long_cold = run("600", "long_cold");
  const std::optional<ChildPeak> long_warm = run("600", "long_warm");
  ASSERT_TRUE(short_run && long_cold && long_warm)
      << "hilrig did not start or did not finish in time";
  for (const ChildPeak& peak : {*short_run, *long_cold, *long_warm}) {
    ASSERT_TRUE(WIFEXITED(peak.status) && WEXITSTATUS(peak.status) == 0);
  }
  EXPECT_GT(short_run->max_rss_kb, 0);
  for (const ChildPeak& peak : {*long_cold, *long_warm}) {
    EXPECT_LT(peak.max_rss_kb, short_run->max_rss_kb + 4 * 1024)
        << "peak resident size: " << short_run->max_rss_kb << " KiB over 60 s, " << peak.max_rss_kb
        << " KiB over 600 s";
  }
  // Both long runs were compared with the whole reference, the second one from the cache.
  const std::string cold = ReadFile(dir / "long_cold" / "report.json");
  const std::string warm = ReadFile(dir / "long_warm" / "report.json");
  EXPECT_NE(cold.find("\"samples_compared\": \"60000\""), std::string::npos) << cold;
  EXPECT_NE(warm.find("\"reference_cached\": true"), std::string::npos) << warm;
}

}  // namespace
}  // namespace hilrig::host
