// A child process the harness starts and owns (the DUT emulator of a multi-process run): spawned
// without a shell, bound to die with the harness, watched without blocking (so a watchdog can
// notice it died), and ended with SIGTERM, then SIGKILL if it does not go, and always reaped. The
// platform part of the HIL link, kept apart from the protocol (hil_link_codec) and the transport
// (hil_link_socket).
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rig/result.h"

namespace hilrig::host {

class ChildProcess {
 public:
  // Starts argv[0] (a path, not searched in PATH) with argv, in a process group of its own, bound
  // to be killed (SIGKILL) when the thread that started it ends, which in the single-threaded
  // harness is when the harness ends, however it ends: a SIGKILLed hilrig leaves no QEMU, dut_emu
  // or sweep shard behind. It gets this process's environment plus `environment` ("NAME=value"
  // each, replacing a variable of the same name): what only the child may know goes there, never
  // in argv, which every user can read.
  // The descriptors in `inherited_fds` stay open in the child under the same numbers (even when
  // close-on-exec here); every other close-on-exec descriptor closes as usual.
  static rig::Result<ChildProcess> Spawn(const std::vector<std::string>& argv,
                                         const std::vector<std::string>& environment = {},
                                         const std::vector<int>& inherited_fds = {});
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  // Terminate()s a child still running.
  ~ChildProcess();

  pid_t pid() const { return pid_; }
  // Without blocking: nullopt while it runs, else how it ended ("exited with status 3",
  // "killed by signal 9"). Reaps it.
  std::optional<std::string> PollExit();
  // SIGTERM, up to grace_ms for it to exit, then SIGKILL; reaps. Returns how it ended. grace_ms 0:
  // SIGKILL at once, for a child with nothing to save.
  std::string Terminate(int grace_ms = 500);
  // The status it exited with, once PollExit or Terminate saw it exit; unset while it runs or
  // when a signal ended it.
  std::optional<int> exit_status() const { return exit_status_; }

 private:
  explicit ChildProcess(pid_t pid) : pid_(pid) {}
  void Ended(int wait_status);
  pid_t pid_ = -1;
  std::optional<std::string> exit_;
  std::optional<int> exit_status_;
};

struct CommandOutput {
  std::optional<int> exit_status;  // unset when a signal or a stop request ended it
  std::string ended;               // "exited with status 1", "killed by signal 15"
  std::string output;              // its standard output (standard error passes through)
};

// Runs argv (argv[0] a path) to its end and returns what it printed on standard output, at most
// `max_output_bytes` of it (the rest is read and dropped, so the child never blocks on a full
// pipe). A stop request ends the child (SIGTERM, then SIGKILL). Fails only when it cannot start.
rig::Result<CommandOutput> RunCapturingOutput(const std::vector<std::string>& argv,
                                              const std::atomic<bool>* stop_requested,
                                              std::size_t max_output_bytes = 1 << 20);

// The first executable `name` in the directories of $PATH; the error names it and the search.
rig::Result<std::string> FindInPath(const std::string& name);

// Directory of the running executable (/proc/self/exe), for finding sibling executables.
rig::Result<std::string> ExecutableDirectory();

}  // namespace hilrig::host
