// Entry point of the hilrig CLI: turns SIGINT/SIGTERM into a stop request so that an interrupted
// command still writes out what it finished, then hands over to RunCli. Every command looks at the
// request between steps of its work, and every wait in hilrig is a poll(2) with a timeout, which
// a signal interrupts whatever the flags; the handlers restart reads and writes, so a write to a
// slow pipe on stdout is not cut by the signal and what was finished still gets out. A second
// signal ends the process at once, for whatever would not stop.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <iostream>

#include "host/cli/cli.h"
#include "rig/file_io.h"
#include "rig/printable_text.h"

namespace {

std::atomic<bool> stop_requested{false};

extern "C" void RequestStop(int signal_number) {
  if (!stop_requested.exchange(true)) return;
  // The signal is blocked while its handler runs: raised here, it ends the process on return.
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = RequestStop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

// std::cout would lose why a write failed; this buffer keeps the errno of the first failure. A
// terminal gets every line at once (progress lines of a long run), anything else a buffer.
std::size_t StdoutBufferBytes() { return ::isatty(STDOUT_FILENO) ? 0 : std::size_t{64} << 10; }

}  // namespace

int main(int argc, char** argv) {
  static_assert(std::atomic<bool>::is_always_lock_free);
  InstallStopHandlers();
  const std::vector<std::string> args(argv + 1, argv + argc);
  hilrig::rig::FdStreamBuf stdout_buffer(STDOUT_FILENO, StdoutBufferBytes());
  // What a command prints may quote what came from outside (a board's name, a peer's reason, a
  // file name): neither stream lets a control character through to the terminal.
  hilrig::rig::PrintableStreamBuf printable_stdout(&stdout_buffer);
  hilrig::rig::PrintableStreamBuf printable_stderr(std::cerr.rdbuf());
  std::ostream out(&printable_stdout);
  std::ostream err(&printable_stderr);
  err.setf(std::ios::unitbuf);
  // Reading standard input flushes what was printed first, so decode answers line by line.
  std::cin.tie(&out);
  int exit_code = hilrig::host::RunCli(args, out, err, &stop_requested);
  // Output that never arrived (a full disk, a closed descriptor) is no success.
  out.flush();
  if (!stdout_buffer.Close() || !out) {
    const int error_number = stdout_buffer.error_number();
    std::cerr << "hilrig: cannot write to standard output"
              << (error_number != 0 ? std::string(": ") + std::strerror(error_number) : "") << "\n";
    exit_code = std::max(exit_code, hilrig::host::kExitBadInput);
  }
  return exit_code;
}
