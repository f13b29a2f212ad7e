// Runs the hilrig CLI in-process for tests and keeps what it printed: one helper for every test
// folder that drives a command (run, check, calibrate, bench, ...).
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "host/cli/cli.h"

namespace hilrig::host {

struct CliResult {
  int exit_code;
  std::string out;
  std::string err;
};

// `input` is what the command reads on standard input.
inline CliResult Cli(const std::vector<std::string>& args, const std::string& input = "") {
  std::istringstream in(input);
  std::ostringstream out, err;
  const int exit_code = RunCli(args, out, err, nullptr, &in);
  return {exit_code, out.str(), err.str()};
}

}  // namespace hilrig::host
