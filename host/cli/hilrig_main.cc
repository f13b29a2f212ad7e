// Entry point of the hilrig CLI: turns SIGINT/SIGTERM into a stop request so that an interrupted
// run still writes its report and logs, then hands over to RunCli.
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <iostream>

#include "host/cli/cli.h"
#include "rig/file_io.h"

namespace {

std::atomic<bool> stop_requested{false};

extern "C" void RequestStop(int /*signal*/) { stop_requested.store(true); }

// std::cout would lose why a write failed; this buffer keeps the errno of the first failure. A
// terminal gets every line at once (progress lines of a long run), anything else a buffer.
std::size_t StdoutBufferBytes() { return ::isatty(STDOUT_FILENO) ? 0 : std::size_t{64} << 10; }

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  const std::vector<std::string> args(argv + 1, argv + argc);
  hilrig::rig::FdStreamBuf stdout_buffer(STDOUT_FILENO, StdoutBufferBytes());
  std::ostream out(&stdout_buffer);
  // Reading standard input flushes what was printed first, so decode answers line by line.
  std::cin.tie(&out);
  int exit_code = hilrig::host::RunCli(args, out, std::cerr, &stop_requested);
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
