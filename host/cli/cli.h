// The `hilrig` command line: `run` (one scenario file or every scenario in a folder), `check`
// (validate specs without running them) and `help`. Written against streams and an argument list
// so tests drive it in-process; hilrig_main.cc only wires it to the process. Exit codes: 0 every
// check met its expected verdict, 1 one did not (or the run was cut short), 2 bad input or usage.
#pragma once

#include <atomic>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace hilrig::host {

inline constexpr int kExitPass = 0;
inline constexpr int kExitCheckFailed = 1;
inline constexpr int kExitBadInput = 2;

// `args` excludes the program name. `stop_requested` (optional) ends a command early, e.g. on
// SIGINT; `in` (default: the process's standard input, read so that a stop request ends the
// wait) feeds `decode`.
int RunCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
           const std::atomic<bool>* stop_requested = nullptr, std::istream* in = nullptr);

}  // namespace hilrig::host
