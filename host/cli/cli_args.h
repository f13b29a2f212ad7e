// Argument parsing shared by the hilrig subcommands: the rig's option parser (rig/command_args.h),
// the streams a subcommand writes to, and the options every subcommand reads alike.
#pragma once

#include <atomic>
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "rig/command_args.h"
#include "rig/result.h"

namespace hilrig::host {

struct CliStreams {
  std::ostream& out;
  std::ostream& err;
  const std::atomic<bool>* stop_requested;
};

// The parser itself is the rig's, shared with dut_emu.
using rig::CliArgs;
using rig::ParseCliArgs;

rig::Result<std::uint64_t> ParseSeed(const std::string& text);

// Removes every `flag` (an option without a value) from args[1..]; true if there was one.
bool TakeFlag(std::vector<std::string>& args, const std::string& flag);

// The value of `option`: a whole number from `min` to `max`, the whole text and nothing else.
rig::Result<int> ParseWholeNumberOption(const std::string& option, const std::string& text, int min,
                                        int max);

// --duration-s: a positive, finite number of seconds, the whole text and nothing else.
rig::Result<double> ParseDurationOption(const std::string& text);

// --set PATH=VALUE[,PATH=VALUE...]: numbers of the spec by field path, in order. Only the form is
// checked here (a path, "=", a number); whether the spec has the field is the run's to say.
rig::Result<std::vector<std::pair<std::string, double>>> ParseSetOption(const std::string& text);

}  // namespace hilrig::host
