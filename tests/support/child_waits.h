// The real hilrig binary as a child process, for what only a process shows: a signal, a SIGKILL,
// two runs at once. Every wait is a bounded poll loop with a deadline (short naps between looks
// at the child or its files), never a fixed sleep standing in for an event.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

#include "host/link/child_process.h"
#include "rig/clock.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {

inline std::string HilrigBinary() { return ::hilrig::test_support::BinDir() + "/hilrig"; }

// Runs `command` through /bin/sh (for its redirections), which execs it: the child's pid is the
// command's.
inline ChildProcess StartShellCommand(const std::string& command) {
  auto child = ChildProcess::Spawn({"/bin/sh", "-c", "exec " + command});
  EXPECT_TRUE(child) << child.error().message;
  return std::move(child).value();
}

// True once `done()` holds; false if `deadline_s` of wall time pass first.
template <typename Predicate>
bool WaitUntil(Predicate done, double deadline_s) {
  const rig::SteadyClock clock;
  const std::int64_t end_ns = clock.NowNs() + static_cast<std::int64_t>(deadline_s * 1e9);
  const timespec nap{0, 2'000'000};
  while (!done()) {
    if (clock.NowNs() > end_ns) return false;
    ::nanosleep(&nap, nullptr);
  }
  return true;
}

// How the child ended ("exited with status 1"), or nullopt while it still runs after deadline_s.
inline std::optional<std::string> WaitForExit(ChildProcess& child, double deadline_s) {
  std::optional<std::string> ended;
  WaitUntil([&] { return (ended = child.PollExit()).has_value(); }, deadline_s);
  return ended;
}

// The process runs `program` and has its handler for `signal` in place: past its start-up.
inline bool CatchesSignal(pid_t pid, const std::string& program, int signal) {
  const std::string proc = "/proc/" + std::to_string(pid);
  if (ReadFile(proc + "/comm") != program + "\n") return false;
  std::istringstream status(ReadFile(proc + "/status"));
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigCgt:", 0) != 0) continue;
    const std::uint64_t caught = std::strtoull(line.c_str() + 7, nullptr, 16);
    return (caught >> (signal - 1) & 1) != 0;
  }
  return false;
}

// The CPU time the process has used so far (user and system, /proc/PID/stat).
inline double CpuSeconds(pid_t pid) {
  const std::string stat = ReadFile("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t name_end = stat.rfind(')');
  if (name_end == std::string::npos) return 0;
  std::istringstream fields(stat.substr(name_end + 2));
  std::string field;
  std::uint64_t ticks = 0;
  // After the name: state is field 3; utime and stime are fields 14 and 15.
  for (int index = 3; index <= 15 && fields >> field; ++index) {
    if (index >= 14) ticks += std::stoull(field);
  }
  return static_cast<double>(ticks) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

}  // namespace hilrig::host
