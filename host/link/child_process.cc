#include "host/link/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string_view>

extern char** environ;

namespace hilrig::host {
namespace {

// environ with `added` appended and any variable `added` names left out.
std::vector<char*> ChildEnvironment(const std::vector<std::string>& added) {
  std::vector<char*> variables;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string_view variable(*entry);
    const std::string_view name = variable.substr(0, variable.find('='));
    const bool replaced = std::any_of(added.begin(), added.end(), [&](const std::string& a) {
      return a.size() > name.size() && a.compare(0, name.size(), name) == 0 &&
             a[name.size()] == '=';
    });
    if (!replaced) variables.push_back(*entry);
  }
  for (const std::string& variable : added)
    variables.push_back(const_cast<char*>(variable.c_str()));
  variables.push_back(nullptr);
  return variables;
}

std::string DescribeStatus(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "ended with wait status " + std::to_string(status);
}

// A descriptor the child gets under another number (or, `from` == `to`, keeps across exec).
struct FdMove {
  int from;
  int to;
};

// The child's side of SpawnInOwnGroup, between fork and exec: async-signal-safe calls only. An
// exec that fails writes its errno to `status_fd` for the parent.
[[noreturn]] void BecomeChild(pid_t parent, char* const* args, char* const* variables,
                              const std::vector<FdMove>& moves, int status_fd) {
  // The child dies with this process, however it ends (a SIGKILL included), so that no DUT process
  // or QEMU keeps running with its ports open, and no sweep shard keeps running cases. The
  // setting survives exec; a parent that died before it took effect is caught by the check.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(127);
  ::setpgid(0, 0);
  for (const FdMove& move : moves) {
    // dup2 clears close-on-exec on the new number; onto itself it does nothing, so clear it here.
    if (move.from == move.to) {
      ::fcntl(move.from, F_SETFD, 0);
    } else {
      ::dup2(move.from, move.to);
    }
  }
  ::execve(args[0], args, variables);
  const int error = errno;
  (void)!::write(status_fd, &error, sizeof(error));
  ::_exit(127);
}

// Starts argv[0] (a path; argv not empty) with argv, this process's environment plus
// `environment` (as ChildEnvironment) and the descriptors `moves`, in a process group of its own
// (a Ctrl-C at the terminal reaches the harness, which then ends the child itself, instead of both
// racing to stop) and bound to die with this process (PR_SET_PDEATHSIG). Fails, naming the
// program, when it cannot be forked or exec'd (a missing or non-executable program).
rig::Result<pid_t> SpawnInOwnGroup(const std::vector<std::string>& argv,
                                   const std::vector<std::string>& environment,
                                   const std::vector<FdMove>& moves) {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  std::vector<char*> variables = ChildEnvironment(environment);
  int status_pipe[2];
  if (::pipe2(status_pipe, O_CLOEXEC) != 0) {
    return rig::MakeError("cannot start " + argv[0] + ": pipe: " + std::strerror(errno));
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) BecomeChild(parent, args.data(), variables.data(), moves, status_pipe[1]);
  const int fork_error = errno;
  ::close(status_pipe[1]);
  if (pid < 0) {
    ::close(status_pipe[0]);
    return rig::MakeError("cannot start " + argv[0] + ": fork: " + std::strerror(fork_error));
  }
  // The pipe closes at a successful exec (close-on-exec) and brings the errno of a failed one.
  int exec_error = 0;
  ssize_t got = 0;
  do {
    got = ::read(status_pipe[0], &exec_error, sizeof(exec_error));
  } while (got < 0 && errno == EINTR);
  ::close(status_pipe[0]);
  if (got == static_cast<ssize_t>(sizeof(exec_error))) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return rig::MakeError("cannot start " + argv[0] + ": " + std::strerror(exec_error));
  }
  return pid;
}

}  // namespace

rig::Result<ChildProcess> ChildProcess::Spawn(const std::vector<std::string>& argv,
                                              const std::vector<std::string>& environment,
                                              const std::vector<int>& inherited_fds) {
  if (argv.empty()) return rig::MakeError("no program to start");
  std::vector<FdMove> moves;
  for (const int fd : inherited_fds) moves.push_back({fd, fd});
  const rig::Result<pid_t> spawned = SpawnInOwnGroup(argv, environment, moves);
  if (!spawned.ok()) return spawned.error();
  return ChildProcess(spawned.value());
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(other.pid_), exit_(std::move(other.exit_)), exit_status_(other.exit_status_) {
  other.pid_ = -1;
}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
  if (this != &other) {
    if (pid_ > 0 && !exit_) Terminate();
    pid_ = other.pid_;
    exit_ = std::move(other.exit_);
    exit_status_ = other.exit_status_;
    other.pid_ = -1;
  }
  return *this;
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exit_) Terminate();
}

std::optional<std::string> ChildProcess::PollExit() {
  if (exit_ || pid_ <= 0) return exit_;
  int status = 0;
  const pid_t done = ::waitpid(pid_, &status, WNOHANG);
  if (done == pid_) Ended(status);
  if (done < 0 && errno == ECHILD) exit_ = "was reaped elsewhere";
  return exit_;
}

std::string ChildProcess::Terminate(int grace_ms) {
  if (pid_ <= 0) return "not started";
  if (PollExit()) return *exit_;
  if (grace_ms > 0) ::kill(pid_, SIGTERM);
  // Short naps on a child that is going away; bounded by grace_ms.
  const timespec nap{0, 5'000'000};
  for (int waited_ms = 0; waited_ms < grace_ms; waited_ms += 5) {
    if (PollExit()) return *exit_;
    ::nanosleep(&nap, nullptr);
  }
  ::kill(pid_, SIGKILL);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  Ended(status);
  return *exit_;
}

void ChildProcess::Ended(int wait_status) {
  exit_ = DescribeStatus(wait_status);
  if (WIFEXITED(wait_status)) exit_status_ = WEXITSTATUS(wait_status);
}

rig::Result<CommandOutput> RunCapturingOutput(const std::vector<std::string>& argv,
                                              const std::atomic<bool>* stop_requested,
                                              std::size_t max_output_bytes) {
  if (argv.empty()) return rig::MakeError("no program to start");
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    return rig::MakeError("cannot start " + argv[0] + ": pipe: " + std::strerror(errno));
  }
  const rig::Result<pid_t> spawned = SpawnInOwnGroup(argv, {}, {{pipe_fds[1], STDOUT_FILENO}});
  ::close(pipe_fds[1]);
  if (!spawned.ok()) {
    ::close(pipe_fds[0]);
    return spawned.error();
  }
  const pid_t pid = spawned.value();
  CommandOutput result;
  std::array<char, 4096> chunk;
  for (;;) {
    if (stop_requested != nullptr && stop_requested->load()) break;
    pollfd readable{pipe_fds[0], POLLIN, 0};
    if (::poll(&readable, 1, 100) <= 0) continue;
    const ssize_t got = ::read(pipe_fds[0], chunk.data(), chunk.size());
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;  // the child closed its standard output: it is ending
    const std::size_t room = max_output_bytes - std::min(max_output_bytes, result.output.size());
    result.output.append(chunk.data(), std::min(room, static_cast<std::size_t>(got)));
  }
  ::close(pipe_fds[0]);
  // At the end of its output a child is ending on its own; a stopped one is asked to, and then
  // made to.
  int status = 0;
  bool reaped = false;
  if (stop_requested != nullptr && stop_requested->load()) {
    ::kill(pid, SIGTERM);
    const timespec nap{0, 5'000'000};
    for (int waited_ms = 0; waited_ms < 1000 && !reaped; waited_ms += 5) {
      reaped = ::waitpid(pid, &status, WNOHANG) == pid;
      if (!reaped) ::nanosleep(&nap, nullptr);
    }
    if (!reaped) ::kill(pid, SIGKILL);
  }
  while (!reaped && ::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.ended = DescribeStatus(status);
  if (WIFEXITED(status) && !(stop_requested != nullptr && stop_requested->load())) {
    result.exit_status = WEXITSTATUS(status);
  }
  return result;
}

rig::Result<std::string> ExecutableDirectory() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return rig::MakeError("cannot read /proc/self/exe: " + error.message());
  return self.parent_path().string();
}

rig::Result<std::string> FindInPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string directories = path != nullptr ? path : "";
  std::size_t start = 0;
  while (start <= directories.size()) {
    const std::size_t end = std::min(directories.find(':', start), directories.size());
    const std::string directory = directories.substr(start, end - start);
    start = end + 1;
    if (directory.empty()) continue;
    const std::string candidate = directory + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return rig::MakeError("no " + name + " in PATH");
}

}  // namespace hilrig::host
