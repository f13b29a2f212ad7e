// Entry point of the hilrig CLI: turns SIGINT/SIGTERM into a stop request so that an interrupted
// run still writes its report and logs, then hands over to RunCli.
#include <csignal>
#include <iostream>

#include "host/cli/cli.h"

namespace {

std::atomic<bool> stop_requested{false};

extern "C" void RequestStop(int /*signal*/) { stop_requested.store(true); }

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  const std::vector<std::string> args(argv + 1, argv + argc);
  return hilrig::host::RunCli(args, std::cout, std::cerr, &stop_requested);
}
